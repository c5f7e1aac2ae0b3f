#include "varsfm/calibration/two_view_calibration.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "varsfm/calibration/bougnoux.h"
#include "varsfm/estimators/two_view_estimators.h"
#include "varsfm/geometry/fundamental.h"
#include "varsfm/synthetic/synthetic_scene.h"

namespace varsfm {
namespace {

SyntheticOptions GeneralPair(uint64_t seed) {
  SyntheticOptions o;
  o.num_images = 2;
  o.num_points = 400;
  o.arc_degrees = 25;
  o.look_at_jitter = 0.8;  // optical axes do not meet: the general configuration
  o.focal_start = 700 + (seed % 7) * 100;
  o.focal_end = o.focal_start * 1.4;
  o.seed = seed;
  return o;
}

Eigen::Matrix3d TrueF(const SyntheticScene& s) {
  return FundamentalFromPose(s.cameras[0].K(), s.cameras[1].K(), s.poses[1] * s.poses[0].Inverse());
}

TEST(Bougnoux, ExactOnNoiseFreeGeneralPairs) {
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    const SyntheticScene s = GenerateSyntheticScene(GeneralPair(seed));
    const auto focals =
        BougnouxFocalLengths(TrueF(s), s.cameras[0].K().col(2).head<2>(), s.cameras[1].K().col(2).head<2>());
    ASSERT_TRUE(focals.has_value()) << "seed " << seed;
    EXPECT_NEAR(focals->first / s.cameras[0].focal(), 1.0, 1e-6) << "seed " << seed;
    EXPECT_NEAR(focals->second / s.cameras[1].focal(), 1.0, 1e-6) << "seed " << seed;
  }
}

TEST(TwoViewCalibration, FocalWithinOnePercentAtHalfPixelNoise) {
  std::vector<double> errors;
  for (uint64_t seed = 1; seed <= 30; ++seed) {
    SyntheticOptions o = GeneralPair(seed);
    o.noise_sigma = 0.5;
    const SyntheticScene s = GenerateSyntheticScene(o);
    std::vector<Eigen::Vector2d> x1, x2;
    s.Correspondences(0, 1, &x1, &x2);
    RansacOptions ransac;
    ransac.max_error = 1.5;
    ransac.seed = seed;
    const auto F = EstimateFundamentalMatrix(x1, x2, ransac);
    ASSERT_TRUE(F.success);
    TwoViewCalibrationOptions options;
    options.refine_distortion = false;
    const TwoViewCalibration calib =
        CalibrateTwoView(x1, x2, o.width, o.height, o.width, o.height, F.model, options);
    ASSERT_TRUE(calib.success) << "seed " << seed;
    if (calib.degenerate) continue;
    errors.push_back(std::abs(calib.camera1.focal() / s.cameras[0].focal() - 1));
    errors.push_back(std::abs(calib.camera2.focal() / s.cameras[1].focal() - 1));
    EXPECT_LT(calib.rms_px, 0.7);
  }
  ASSERT_GE(errors.size(), 40u);  // most random general pairs are not flagged
  std::sort(errors.begin(), errors.end());
  const double median = errors[errors.size() / 2];
  const double p90 = errors[errors.size() * 9 / 10];
  RecordProperty("median_focal_error", std::to_string(median));
  EXPECT_LT(median, 0.01);
  EXPECT_LT(p90, 0.03);
  std::printf("focal error: median %.3f %%, 90th percentile %.3f %% over %zu focal lengths\n",
              100 * median, 100 * p90, errors.size());
}

TEST(TwoViewCalibration, IntersectingOpticalAxesAreFlaggedDegenerate) {
  SyntheticOptions o = GeneralPair(3);
  o.look_at_jitter = 0.0;  // every optical axis passes through the origin
  o.noise_sigma = 0.5;
  const SyntheticScene s = GenerateSyntheticScene(o);
  std::vector<Eigen::Vector2d> x1, x2;
  s.Correspondences(0, 1, &x1, &x2);
  const TwoViewCalibration calib =
      CalibrateTwoView(x1, x2, o.width, o.height, o.width, o.height, TrueF(s), {});
  EXPECT_TRUE(calib.degenerate);
  EXPECT_FALSE(calib.degeneracy_reason.empty());
  // The fallback still gives a usable pose and points (focal at the prior).
  EXPECT_TRUE(calib.success);
  EXPECT_DOUBLE_EQ(calib.camera1.focal(), 1.2 * o.width);
}

}  // namespace
}  // namespace varsfm
