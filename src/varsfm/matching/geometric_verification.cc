#include "varsfm/matching/geometric_verification.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/core/eigen.hpp>

#include "varsfm/estimators/neighbourhood_graph.h"
#include "varsfm/estimators/two_view_estimators.h"
#include "varsfm/util/error.h"
#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

struct RobustFit {
  Eigen::Matrix3d model = Eigen::Matrix3d::Zero();
  std::vector<uchar> inlier_mask;
  int num_inliers = 0;
};

double InlierThreshold(const VerificationOptions& options, bool homography) {
  return homography ? options.homography_max_error : options.max_error;
}

cv::UsacParams MakeUsacParams(const VerificationOptions& options, bool homography, uint64_t seed) {
  cv::UsacParams params;
  params.confidence = options.confidence;
  params.maxIterations = options.max_num_trials;
  params.threshold = InlierThreshold(options, homography);
  params.isParallel = false;  // pairs already run in parallel
  params.randomGeneratorState = static_cast<int>(seed & 0x7fffffff);
  params.sampler = cv::SAMPLING_UNIFORM;
  params.neighborsSearch = cv::NEIGH_GRID;
  // The settings OpenCV's USAC_MAGSAC / USAC_ACCURATE flags choose (usac/ransac_solvers.cpp).
  if (options.method == RansacMethod::kUsacMagsac) {
    params.score = cv::SCORE_METHOD_MAGSAC;
    params.loMethod = cv::LOCAL_OPTIM_SIGMA;
    params.loSampleSize = homography ? 75 : 50;
    params.loIterations = homography ? 15 : 10;
  } else {
    params.score = cv::SCORE_METHOD_MSAC;
    params.loMethod = cv::LOCAL_OPTIM_GC;
    params.loSampleSize = 20;
    params.loIterations = 25;
  }
  return params;
}

// A pair's matched keypoints in the form its estimator reads: OpenCV's points, or the project's
// with, for graph-cut RANSAC, the neighbourhood it smooths over (built once for F and H).
struct MatchedPoints {
  std::vector<cv::Point2d> cv1, cv2;
  std::vector<Eigen::Vector2d> x1, x2;
  NeighbourhoodGraph neighbourhood;
};

bool UsesOwnRansac(RansacMethod method) {
  return method == RansacMethod::kLoRansac || method == RansacMethod::kGraphCut;
}

// F or H by the project's RANSAC (estimators/ransac.h), with graph-cut local optimisation for
// kGraphCut and, for F, DEGENSAC unless options say otherwise.
RobustFit FitOwn(const MatchedPoints& points, bool homography, const VerificationOptions& options,
                 uint64_t seed) {
  RansacOptions ransac;
  ransac.max_error = InlierThreshold(options, homography);
  ransac.confidence = options.confidence;
  ransac.max_iterations = options.max_num_trials;
  ransac.spatial_coherence = options.spatial_coherence;
  ransac.degeneracy_recovery = options.degeneracy_recovery;
  ransac.seed = seed;
  const NeighbourhoodGraph* graph =
      options.method == RansacMethod::kGraphCut ? &points.neighbourhood : nullptr;
  const RansacReport<Eigen::Matrix3d> report =
      homography ? EstimateHomography(points.x1, points.x2, ransac, graph)
                 : EstimateFundamentalMatrix(points.x1, points.x2, ransac, graph);
  RobustFit fit;
  if (!report.success) return fit;
  fit.model = report.model;
  fit.inlier_mask.assign(report.inlier_mask.begin(), report.inlier_mask.end());
  fit.num_inliers = static_cast<int>(report.num_inliers);
  return fit;
}

RobustFit Fit(const MatchedPoints& points, bool homography, const VerificationOptions& options,
              uint64_t seed) {
  if (UsesOwnRansac(options.method)) return FitOwn(points, homography, options, seed);
  const std::vector<cv::Point2d>& points1 = points.cv1;
  const std::vector<cv::Point2d>& points2 = points.cv2;
  RobustFit fit;
  cv::Mat model;
  if (options.method == RansacMethod::kRansac) {
    // The classic estimators draw from cv::theRNG(), which is per thread: seeding it right
    // before the call makes the result independent of scheduling.
    cv::theRNG().state = seed | 1;
    const double threshold = InlierThreshold(options, homography);
    model =
        homography
            ? cv::findHomography(points1, points2, cv::RANSAC, threshold, fit.inlier_mask,
                                 options.max_num_trials, options.confidence)
            : cv::findFundamentalMat(points1, points2, cv::FM_RANSAC, threshold, options.confidence,
                                     options.max_num_trials, fit.inlier_mask);
  } else {
    const cv::UsacParams params = MakeUsacParams(options, homography, seed);
    model = homography ? cv::findHomography(points1, points2, fit.inlier_mask, params)
                       : cv::findFundamentalMat(points1, points2, fit.inlier_mask, params);
  }
  // A failed fit returns an empty matrix (the 7-point solver may also return up to three
  // stacked solutions when given exactly 7 points; those are not a verified model).
  if (model.rows != 3 || model.cols != 3) {
    fit.inlier_mask.clear();
    return fit;
  }
  cv::cv2eigen(model, fit.model);
  fit.num_inliers = cv::countNonZero(fit.inlier_mask);
  return fit;
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
  const bool own = UsesOwnRansac(options.method);
  for (const FeatureMatch& m : matches) {
    if (m.point2D_idx1 >= keypoints1.size() || m.point2D_idx2 >= keypoints2.size()) {
      Fail("match ({}, {}) refers to a missing keypoint ({} and {} keypoints)", m.point2D_idx1,
           m.point2D_idx2, keypoints1.size(), keypoints2.size());
    }
    const FeatureKeypoint& k1 = keypoints1[m.point2D_idx1];
    const FeatureKeypoint& k2 = keypoints2[m.point2D_idx2];
    if (own) {
      points.x1.emplace_back(k1.x, k1.y);
      points.x2.emplace_back(k2.x, k2.y);
    } else {
      points.cv1.emplace_back(k1.x, k1.y);
      points.cv2.emplace_back(k2.x, k2.y);
    }
  }
  if (options.method == RansacMethod::kGraphCut)
    points.neighbourhood =
        CorrespondenceNeighbourhood(points.x1, points.x2, options.mean_neighbours);
  // Different streams for F and H, both fixed by the caller's seed.
  const RobustFit f = Fit(points, false, options, DeriveSeed(options.seed, 0));
  if (f.num_inliers < options.min_num_inliers) return geometry;
  const RobustFit h = Fit(points, true, options, DeriveSeed(options.seed, 1));

  geometry.F = f.model;
  geometry.H = h.model;
  const RobustFit& best = h.num_inliers > f.num_inliers ? h : f;
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
