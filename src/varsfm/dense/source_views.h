#pragma once
// The source views of each reference view for multi-view stereo, chosen from the sparse model as
// Goesele et al. ("Multi-View Stereo for Community Photo Collections", ICCV 2007, section 4.1)
// score them: every 3D point both views see adds w_angle * w_scale to the pair's score, where
// w_angle = min(angle / good_angle, 1)^2 favours wide triangulation angles up to good_angle and
// w_scale favours views that see the point at about the reference's resolution. They are taken
// one at a time, each point's weight falling once enough chosen sources see it (their global
// selection likewise discounts views redundant with those already chosen), so the sources cover
// the reference. And the depth range PatchMatch searches, from the sparse points a view sees.
#include <map>
#include <vector>

#include "varsfm/scene/reconstruction.h"

namespace varsfm {

struct SourceViewOptions {
  int num_source_views = 4;
  int min_shared_points = 15;    // fewer: not a source
  double min_angle_deg = 1.0;    // points below this angle add nothing (no depth information)
  double good_angle_deg = 10.0;  // the angle from which w_angle is 1
  // Sources are chosen one at a time; a point that covered_views chosen sources already see adds
  // redundant_point_weight x its weight to the next source's score (1: the plain ranking), so the
  // later sources see what the first ones do not (PatchMatch's cost comes from the sources that
  // see a pixel, PatchMatchOptions::num_best_views). Ranked by score alone, a view's sources
  // crowd on the side with the widest angles and leave its other side unmatched (bench/results,
  // 2026-12-04-source-coverage.md).
  int covered_views = 2;
  double redundant_point_weight = 0.03;
  // After num_source_views, one more: the view that sees the most of the reference's sparse
  // points no chosen source sees, when it sees at least min_shared_points of them.
  bool coverage_source = true;
  // PatchMatch's depth range per view (SparseDepthRange): 0 spans every sparse point it sees.
  double depth_range_percentile = 1.0;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

// For each registered image (the keys), its best source views, best first; images with none are
// left out.
// The registered images that observe `point`, sorted, each once (a track may hold an image twice).
std::vector<image_t> RegisteredViews(const Reconstruction& reconstruction, const Point3D& point);

std::map<image_t, std::vector<image_t>> SelectSourceViews(const Reconstruction& reconstruction,
                                                          const SourceViewOptions& options);

// For each of `views`, the others that share the most sparse points with it (ties: the earlier in
// `views`), at most `max_views` of them, as indices into `views` in ascending order; every other
// view when there are no more than `max_views`. Fusion checks a depth against these views only:
// against all of them the check grew with the square of the number of views (COLMAP's fusion
// likewise checks its check_num_images most overlapping images).
std::vector<std::vector<uint32_t>> OverlappingViews(const Reconstruction& reconstruction,
                                                    const std::vector<image_t>& views,
                                                    int max_views);

struct DepthRange {
  double min_depth = 0, max_depth = 0;  // 0, 0: the image sees no point in front of it
};

// The `percentile`-th to (100 - `percentile`)-th percentile of the depths of the sparse points
// the image observes (points nearer than a tenth of their median left out), widened by a quarter
// at each end (surfaces beyond the sparse points, e.g. a ground plane running out).
DepthRange SparseDepthRange(const Reconstruction& reconstruction, image_t image_id,
                            double percentile = 1.0);

}  // namespace varsfm
