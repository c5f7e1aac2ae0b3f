#include "varsfm/matching/geometric_verification.h"

#include "varsfm/estimators/neighbourhood_graph.h"
#include "varsfm/estimators/two_view_estimators.h"
#include "varsfm/util/error.h"
#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

// A pair's matched keypoints, with, for graph-cut RANSAC, the neighbourhood it smooths over
// (built once for F and H).
struct MatchedPoints {
  std::vector<Eigen::Vector2d> x1, x2;
  NeighbourhoodGraph neighbourhood;
};

// F or H by the project's RANSAC, with the local optimisation the method names and, for F,
// DEGENSAC unless options say otherwise. A failed fit has no inliers and a zero model.
RansacReport<Eigen::Matrix3d> Fit(const MatchedPoints& points, bool homography,
                                  const VerificationOptions& options, uint64_t seed) {
  RansacOptions ransac;
  ransac.max_error = homography ? options.homography_max_error : options.max_error;
  ransac.confidence = options.confidence;
  ransac.max_iterations = options.max_num_trials;
  ransac.local_optimization = options.method != RansacMethod::kMsac;
  ransac.spatial_coherence = options.spatial_coherence;
  ransac.degeneracy_recovery = options.degeneracy_recovery;
  ransac.seed = seed;
  const NeighbourhoodGraph* graph =
      options.method == RansacMethod::kGraphCut ? &points.neighbourhood : nullptr;
  RansacReport<Eigen::Matrix3d> report =
      homography ? EstimateHomography(points.x1, points.x2, ransac, graph)
                 : EstimateFundamentalMatrix(points.x1, points.x2, ransac, graph);
  if (!report.success) report.model.setZero();
  return report;
}

}  // namespace

TwoViewGeometry VerifyTwoViewGeometry(const FeatureKeypoints& keypoints1,
                                      const FeatureKeypoints& keypoints2,
                                      const FeatureMatches& matches,
                                      const VerificationOptions& options) {
  TwoViewGeometry geometry;
  geometry.config = TwoViewGeometry::kDegenerate;
  // Fewer matches than the 8 points the fundamental solvers need, or than min_num_inliers,
  // cannot verify anything.
  if (matches.size() < static_cast<size_t>(std::max(options.min_num_inliers, 8))) {
    return geometry;
  }
  MatchedPoints points;
  for (const FeatureMatch& m : matches) {
    if (m.point2D_idx1 >= keypoints1.size() || m.point2D_idx2 >= keypoints2.size()) {
      Fail("match ({}, {}) refers to a missing keypoint ({} and {} keypoints)", m.point2D_idx1,
           m.point2D_idx2, keypoints1.size(), keypoints2.size());
    }
    const FeatureKeypoint& k1 = keypoints1[m.point2D_idx1];
    const FeatureKeypoint& k2 = keypoints2[m.point2D_idx2];
    points.x1.emplace_back(k1.x, k1.y);
    points.x2.emplace_back(k2.x, k2.y);
  }
  if (options.method == RansacMethod::kGraphCut)
    points.neighbourhood =
        CorrespondenceNeighbourhood(points.x1, points.x2, options.mean_neighbours);
  // Different streams for F and H, both fixed by the caller's seed.
  const RansacReport<Eigen::Matrix3d> f = Fit(points, false, options, DeriveSeed(options.seed, 0));
  if (f.num_inliers < static_cast<size_t>(options.min_num_inliers)) return geometry;
  const RansacReport<Eigen::Matrix3d> h = Fit(points, true, options, DeriveSeed(options.seed, 1));

  geometry.F = f.model;
  geometry.H = h.model;
  const RansacReport<Eigen::Matrix3d>& best = h.num_inliers > f.num_inliers ? h : f;
  const double h_f_ratio = static_cast<double>(h.num_inliers) / f.num_inliers;
  geometry.config = h_f_ratio > options.max_H_inlier_ratio ? TwoViewGeometry::kPlanarOrPanoramic
                                                           : TwoViewGeometry::kUncalibrated;
  geometry.inlier_matches.reserve(best.num_inliers);
  for (size_t k = 0; k < matches.size(); ++k) {
    if (best.inlier_mask[k]) geometry.inlier_matches.push_back(matches[k]);
  }
  return geometry;
}

void VerificationOptions::Check() const {
  CheckPositive("--max-error", max_error);
  CheckPositive("--homography-max-error", homography_max_error);
  CheckAtLeast("--min-inliers", min_num_inliers, 1);
  CheckInHalfOpenRange("confidence", confidence, 0, 1);
  CheckAtLeast("max_num_trials", max_num_trials, 1);
  CheckFraction("max_H_inlier_ratio", max_H_inlier_ratio);
  CheckPositive("--gc-neighbours", mean_neighbours);
  CheckFraction("--gc-coherence", spatial_coherence);
}

}  // namespace varsfm
