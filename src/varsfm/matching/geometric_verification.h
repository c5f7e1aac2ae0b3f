#pragma once
// Geometric verification of an image pair's putative matches, as COLMAP's uncalibrated
// two-view estimation does it: a fundamental matrix and a homography by the project's RANSAC
// (estimators/ransac.h), then the pair's configuration from their inlier counts.
#include <cstdint>

#include "varsfm/feature/two_view_geometry.h"
#include "varsfm/feature/types.h"
#include "varsfm/util/enum_names.h"
#include "varsfm/util/random.h"

namespace varsfm {

// Which robust estimator finds F and H: the project's RANSAC (estimators/ransac.h) with MSAC
// scoring and, for F, DEGENSAC's recovery from samples on a dominant plane, with or without a
// local optimisation of each new best model. Without is the default: on a facade the local
// optimisations' least squares on mostly planar inliers tilt F towards groups of wrong matches
// that then fit it within the threshold, and lift H's inlier count over the planarity test's
// ratio (bench/results/2026-12-05-s20-verification.md).
enum class RansacMethod {
  kMsac,      // no local optimisation
  kLoRansac,  // iterated least squares (Lebeda, Matas & Chum 2012)
  kGraphCut,  // graph-cut local optimisation (GC-RANSAC, Barath & Matas 2018)
};

inline constexpr EnumName<RansacMethod> kRansacMethodNames[] = {
    {RansacMethod::kMsac, "msac"},
    {RansacMethod::kLoRansac, "lo-ransac"},
    {RansacMethod::kGraphCut, "gc-ransac"}};

struct VerificationOptions {
  RansacMethod method = RansacMethod::kMsac;
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
  // DEGENSAC for F (estimators/fundamental_degeneracy.h): a model from a sample mostly on one
  // plane, or one that became so in its local optimisation, is recovered by plane and parallax.
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
