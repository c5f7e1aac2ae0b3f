#include "varsfm/calibration/two_view_calibration.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "varsfm/estimators/fundamental_8pt.h"
#include "varsfm/estimators/fundamental_refinement.h"
#include "varsfm/synthetic/synthetic_scene.h"

namespace varsfm {
namespace {

struct Pair {
  SyntheticScene scene;
  std::vector<Eigen::Vector2d> x1, x2;
  Eigen::Matrix3d F;
};

Pair MakePair(const SyntheticOptions& o) {
  Pair p;
  p.scene = GenerateSyntheticScene(o);
  p.scene.Correspondences(0, 1, &p.x1, &p.x2);
  EXPECT_TRUE(Fundamental8pt(p.x1, p.x2, &p.F));
  p.F = RefineFundamentalMatrix(p.x1, p.x2, p.F);
  return p;
}

SyntheticOptions Base(uint64_t seed) {
  SyntheticOptions o;
  o.num_images = 2;
  o.num_points = 500;
  o.arc_degrees = 40.0;
  o.focal_start = 850.0;
  o.focal_end = 1250.0;
  o.look_at_jitter = 1.0;
  o.noise_sigma = 0.5;
  o.seed = seed;
  return o;
}

TwoViewCalibration Calibrate(const Pair& p, const TwoViewCalibrationOptions& options = {}) {
  const Camera& c = p.scene.cameras[0];
  return CalibrateTwoView(p.x1, p.x2, c.width, c.height, c.width, c.height, p.F, options);
}

// After refinement the pair reprojects at the noise floor. With k1, k2 free per image two views
// determine the focal lengths only to a few percent (f, k1, k2 and the baseline are strongly
// correlated over one pair), so the focal accuracy is checked with distortion held. Weakly
// determined pairs (seeds 3 and 8 here: ~10 % focal error at the noise floor) are flagged by
// the uncertainty of log f (focal_uncertainty.h); every pair that is not flagged is within
// 1.5 %.
TEST(TwoViewCalibration, RefinedPairReprojectsAtNoiseFloor) {
  // Random jitter can still bring the optical axes near each other; such pairs are flagged
  // degenerate (tested below) and skipped here.
  int checked = 0;
  std::vector<double> focal_errors;
  for (uint64_t seed = 1; seed <= 8; ++seed) {
    const Pair p = MakePair(Base(seed));
    for (const bool distortion : {false, true}) {
      TwoViewCalibrationOptions options;
      options.refine_distortion = distortion;
      const TwoViewCalibration r = Calibrate(p, options);
      ASSERT_TRUE(r.success) << "seed " << seed;
      if (r.degenerate) {
        std::printf("seed %d distortion %d: degenerate (%s)\n", static_cast<int>(seed), distortion,
                    r.degeneracy_reason.c_str());
        continue;
      }
      ++checked;
      int valid = 0;
      for (char v : r.point_valid) valid += v;
      EXPECT_GT(valid, 0.95 * p.x1.size());
      // 2D RMS at the optimum: sigma sqrt(2 (m - q) / m), m = 4 n residuals, q = 3 n points +
      // 5 pose + 2 focals (+ 4 distortion).
      const double m = 4.0 * valid, q = 3.0 * valid + (distortion ? 11.0 : 7.0);
      const double floor = 0.5 * std::sqrt(2.0 * (m - q) / m);
      EXPECT_NEAR(r.rms_px, floor, 0.1 * floor) << "seed " << seed;
      const double e1 = r.camera1.focal() / p.scene.cameras[0].focal() - 1.0;
      const double e2 = r.camera2.focal() / p.scene.cameras[1].focal() - 1.0;
      const Rigid3d truth = p.scene.poses[1] * p.scene.poses[0].Inverse();
      const double rot_deg =
          r.cam2_from_cam1.rotation.angularDistance(truth.rotation) * 180.0 / M_PI;
      std::printf(
          "seed %d distortion %d: focal errors %.3f %% %.3f %%, rotation error %.3f deg, "
          "rms %.3f px (floor %.3f), std log f %.4f %.4f\n",
          static_cast<int>(seed), distortion, 100 * e1, 100 * e2, rot_deg, r.rms_px, floor,
          r.log_focal_std1, r.log_focal_std2);
      if (!distortion) {
        focal_errors.push_back(std::abs(e1));
        focal_errors.push_back(std::abs(e2));
      }
    }
  }
  EXPECT_GE(checked, 5);
  std::sort(focal_errors.begin(), focal_errors.end());
  ASSERT_GE(focal_errors.size(), 8u);
  EXPECT_LT(focal_errors[focal_errors.size() / 2], 0.01);
  EXPECT_LT(focal_errors.back(), 0.015);
}

// The two weak pairs of the test above (10-11 % focal error at the noise floor) are flagged by
// the uncertainty of log f.
TEST(TwoViewCalibration, UncertainFocalLengthsAreDegenerate) {
  for (const uint64_t seed : {3, 8}) {
    TwoViewCalibrationOptions options;
    options.refine_distortion = false;
    const TwoViewCalibration r = Calibrate(MakePair(Base(seed)), options);
    ASSERT_TRUE(r.success) << "seed " << seed;
    EXPECT_TRUE(r.degenerate) << "seed " << seed;
    EXPECT_NE(r.degeneracy_reason.find("poorly determined"), std::string::npos)
        << r.degeneracy_reason;
    EXPECT_GT(r.log_focal_std1, 0.015);
  }
}

TEST(TwoViewCalibration, IntersectingOpticalAxesAreDegenerate) {
  SyntheticOptions o = Base(7);
  o.look_at_jitter = 0.0;  // both axes through the origin
  TwoViewCalibrationOptions options;
  options.prior_focal1 = 1000.0;
  const TwoViewCalibration r = Calibrate(MakePair(o), options);
  EXPECT_TRUE(r.degenerate);
  EXPECT_FALSE(r.degeneracy_reason.empty());
  EXPECT_EQ(r.camera1.focal(), 1000.0);  // the prior, held through the refinement
  EXPECT_EQ(r.camera2.focal(), 1.2 * 1024);
}

TEST(TwoViewCalibration, PureRotationIsDegenerate) {
  SyntheticOptions o = Base(8);
  o.path = SyntheticOptions::Path::kPureRotation;
  o.arc_degrees = 20.0;
  o.orbit_radius = 3.0;
  const TwoViewCalibration r = Calibrate(MakePair(o));
  EXPECT_TRUE(r.degenerate);
  std::printf("pure rotation: %s\n", r.degeneracy_reason.c_str());
}

}  // namespace
}  // namespace varsfm
