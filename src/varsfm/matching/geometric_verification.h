#pragma once
// Geometric verification of an image pair's putative matches, as COLMAP's uncalibrated
// two-view estimation does it: a fundamental matrix and a homography by RANSAC, then the pair's
// configuration from their inlier counts. By default the robust estimator is OpenCV's USAC; the
// project's own (estimators/ransac.h, with or without graph-cut local optimisation) can stand in
// (RansacMethod): on the planar facade of entry-P10 they keep more wrong matches than USAC
// (bench/results/2026-12-04-gc-ransac.md), so they are not the default yet.
#include <cstdint>

#include "varsfm/feature/two_view_geometry.h"
#include "varsfm/feature/types.h"
#include "varsfm/util/enum_names.h"
#include "varsfm/util/random.h"

namespace varsfm {

// Which robust estimator finds F and H.
enum class RansacMethod {
  kUsacMagsac,    // cv::USAC_MAGSAC: MAGSAC++ score, sigma-consensus local optimisation
  kUsacAccurate,  // cv::USAC_ACCURATE: MSAC score, graph-cut local optimisation
  kRansac,        // classic cv::FM_RANSAC / cv::RANSAC (OpenCV's thread-local RNG, re-seeded)
  kLoRansac,      // the project's LO-RANSAC (estimators/ransac.h), iterated least squares
  kGraphCut,      // the project's RANSAC with graph-cut local optimisation (GC-RANSAC)
};

inline constexpr EnumName<RansacMethod> kRansacMethodNames[] = {
    {RansacMethod::kUsacAccurate, "usac-accurate"},
    {RansacMethod::kUsacMagsac, "usac-magsac"},
    {RansacMethod::kRansac, "opencv-ransac"},
    {RansacMethod::kLoRansac, "lo-ransac"},
    {RansacMethod::kGraphCut, "gc-ransac"}};

struct VerificationOptions {
  RansacMethod method = RansacMethod::kUsacAccurate;
  // Inlier thresholds in pixels: F's on the Sampson distance, H's on the transfer error. F's is
  // tight: on a facade (most matches on one plane) many wrong epipolar geometries fit within a
  // loose one together with the wrong matches along their epipolar lines, and the mapper's
  // focal lengths follow them. H's stays wider: the H / F inlier ratio is the test for planar
  // pairs, which an H judged tightly fails to flag (the sweep of both:
  // bench/results/2026-12-04-s14-verification-threshold.md).
  double max_error = 1.0;
  double homography_max_error = 1.5;
  int min_num_inliers = 15;  // COLMAP's TwoViewGeometryOptions::min_num_inliers
  double confidence = 0.999;
  int max_num_trials = 10000;
  // A pair whose H explains more than this fraction of F's inliers is planar or a pure rotation
  // (COLMAP's max_H_inlier_ratio): F is unreliable there for self-calibration.
  double max_H_inlier_ratio = 0.8;
  // kGraphCut: the neighbourhood's size (estimators/neighbourhood_graph.h) and the weight of
  // equal labels among neighbours (RansacOptions::spatial_coherence).
  double mean_neighbours = 6.0;
  double spatial_coherence = 0.2;
  // kLoRansac, kGraphCut: DEGENSAC for F (estimators/fundamental_degeneracy.h): a model from a
  // sample mostly on one plane, or one that became so in its local optimisation, is recovered
  // by plane and parallax. OpenCV's USAC has its own test.
  bool degeneracy_recovery = true;
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
