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
  // each seen by at least `min_other_views` of the other views that keep their depth maps, from
  // within max_view_angle_deg of the view's own ray (0: no view is redundant). Fusion needs a
  // depth confirmed by two other depth maps and a fused point seen by three (depth_fusion.h), so
  // five others leave a margin.
  double redundant_fraction = 0.8;
  int min_other_views = 5;
  // A view repeats the others only where they see its surface from nearly where it does. At any
  // angle, views a few degrees apart along a facade, each seeing the whole scene, all count as
  // covering one another: the middle views, whose tracks are the longest, went first, and the
  // surfaces they alone saw face-on went with them. Of the angles measured on
  // bench/surface_fscore's rendered scene (10, 15, 20 degrees), 15 is the widest that keeps its
  // F-score (bench/results/2026-12-07-s35-reference-coverage.md).
  double max_view_angle_deg = 15.0;
  // ... and when at most this fraction of its points are points that fusion can make now (seen by
  // its min_fused_views depth-map views) and could not without it: Furukawa et al.'s coverage
  // constraint, which keeps the views that alone reach a surface few views see.
  double max_uncovered_fraction = 0.05;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

// The views of `candidates` that keep their depth maps, in the order given. Views are judged
// one at a time, those whose points have the longest tracks (mean over the points, among the
// candidates) first, ties by image id; a redundant view is dropped at once, so the views judged
// after it count it no more. `min_fused_views`: the depth-map views a fused point needs
// (DepthFusionOptions::min_fused_views). Deterministic. A view that sees no sparse point is kept.
std::vector<image_t> SelectReferenceViews(const Reconstruction& reconstruction,
                                          const std::vector<image_t>& candidates,
                                          const ReferenceViewOptions& options, int min_fused_views);

}  // namespace varsfm
