#pragma once
// Geometric verification of an image pair's putative matches, as COLMAP's uncalibrated
// two-view estimation does it: a fundamental matrix and a homography by RANSAC, then the pair's
// configuration from their inlier counts. For now the robust estimators are OpenCV's; the
// project's own (src/varsfm/estimators) replace them later.
#include <cstdint>

#include "varsfm/feature/two_view_geometry.h"
#include "varsfm/feature/types.h"
#include "varsfm/util/random.h"

namespace varsfm {

// Which OpenCV robust estimator finds F and H.
enum class RansacMethod {
  kUsacMagsac,    // cv::USAC_MAGSAC: MAGSAC++ score, sigma-consensus local optimisation
  kUsacAccurate,  // cv::USAC_ACCURATE: MSAC score, graph-cut local optimisation
  kRansac,        // classic cv::FM_RANSAC / cv::RANSAC (OpenCV's thread-local RNG, re-seeded)
};

struct VerificationOptions {
  RansacMethod method = RansacMethod::kUsacAccurate;
  // Inlier threshold in pixels (Sampson distance for F, transfer error for H).
  double max_error = 1.5;
  int min_num_inliers = 15;  // COLMAP's TwoViewGeometryOptions::min_num_inliers
  double confidence = 0.999;
  int max_num_trials = 10000;
  // A pair whose H explains more than this fraction of F's inliers is planar or a pure rotation
  // (COLMAP's max_H_inlier_ratio): F is unreliable there for self-calibration.
  double max_H_inlier_ratio = 0.8;
  uint64_t seed = kDefaultSeed;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

// Estimates F (x2^T F x1 = 0) and H (x2 ~ H x1) in varsfm pixel coordinates from the putative
// `matches` between `keypoints1` and `keypoints2`. config is kDegenerate (no inliers) when fewer
// than min_num_inliers support F; otherwise kPlanarOrPanoramic or kUncalibrated, with
// inlier_matches those of the model with more support (F unless H has more), as COLMAP.
TwoViewGeometry VerifyTwoViewGeometry(const FeatureKeypoints& keypoints1,
                                      const FeatureKeypoints& keypoints2,
                                      const FeatureMatches& matches,
                                      const VerificationOptions& options = {});

}  // namespace varsfm
