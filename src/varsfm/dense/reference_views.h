#pragma once
// Which views get a depth map. On a large collection many photos see the same surface from
// nearly the same place: their depth maps repeat one another, and PatchMatch and fusion cost
// time in proportion to the depth maps. In the spirit of the image selection of Furukawa et al.
// ("Towards Internet-scale multi-view stereo", CVPR 2010: images whose points the others cover
// are removed, so long as the sparse points stay covered), a view is redundant when
// most of the sparse points it sees are each seen by enough other depth-map views; it stays a
// source view of the others (source_views.h) and a texture view of the model. On a few photos
// per surface -- the tracks of a small set -- no view is redundant, and every view gets its
// depth map as before.
#include <vector>

#include "varsfm/scene/reconstruction.h"

namespace varsfm {

struct ReferenceViewOptions {
  // A view is redundant when at least `redundant_fraction` of the sparse points it sees are
  // each seen by at least `min_other_views` of the other views that keep their depth maps
  // (0: no view is redundant). Fusion needs a depth confirmed by two other depth maps and a fused
  // point seen by three (depth_fusion.h), so five others leave a margin.
  double redundant_fraction = 0.8;
  int min_other_views = 5;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

// The views of `candidates` that keep their depth maps, in the order given. Views are judged
// one at a time, those whose points have the longest tracks (mean over the points, among the
// candidates) first, ties by image id; a redundant view is dropped at once, so the views judged
// after it count it no more. Deterministic. A view that sees no sparse point is kept.
std::vector<image_t> SelectReferenceViews(const Reconstruction& reconstruction,
                                          const std::vector<image_t>& candidates,
                                          const ReferenceViewOptions& options);

}  // namespace varsfm
