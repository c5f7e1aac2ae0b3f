#pragma once
// The held-out views of the novel-view protocol of the view-synthesis literature (LLFF,
// Mildenhall et al. 2019; mip-NeRF 360): with the registered images sorted by name, every N-th
// one (indices 0, N, 2N, ...) takes part in structure from motion but not in densification or
// texturing, and the finished model is scored by rendering it from those cameras. Source views
// flatter a textured model, whose texture was cut from those very photos.
#include <vector>

#include "varsfm/scene/reconstruction.h"

namespace varsfm {

// Throws OptionError (util/option_check.h) unless `every` is 0 (no held-out views) or at least 2.
void CheckHoldout(int every);

// The registered images held out for `every` (0: none; 1 would hold out every image and is
// refused by the options that take it). In name order.
std::vector<image_t> HeldOutImageIds(const Reconstruction& reconstruction, int every);

// Unregisters the held-out images (their observations leave the tracks), so that a stage run on
// the result never sees them. Returns how many were held out.
size_t HoldOutImages(Reconstruction* reconstruction, int every);

}  // namespace varsfm
