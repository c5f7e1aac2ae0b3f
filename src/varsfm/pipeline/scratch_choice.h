#pragma once
// Where a stage keeps its views' images: on the heap, or in scratch memory
// (util/scratch_memory.h) that the kernel can write out to disk when RAM runs short.
#include <cstddef>
#include <filesystem>

#include "varsfm/scene/reconstruction.h"

namespace varsfm {

// The bytes of `bytes_per_pixel` per pixel of every registered view of `rec`, each scaled to at
// most `max_size` pixels on its longer side.
size_t ViewBytes(const Reconstruction& rec, int max_size, size_t bytes_per_pixel);

// The folder for a stage's scratch memory: the disk of `output` (its nearest existing folder, as
// the output folder may not exist yet) where `view_bytes` exceed a quarter of the usable memory
// (util/usable_memory.h), and none (the heap) where they fit easily. The kernel writes scratch
// pages back to disk whether or not RAM runs short (~12 MB a view at 800 px; docs/measurements.md,
// "The views in scratch memory"), so a stage pays that only where the views could push it out of
// memory. The rest of the stage (the fused cloud, the filters' flags) needs the other three
// quarters.
// `what` names the views in the line that says scratch memory was chosen.
std::filesystem::path ScratchFolderFor(const std::filesystem::path& output, size_t view_bytes,
                                       const char* what);

}  // namespace varsfm
