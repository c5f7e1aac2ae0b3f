#include "varsfm/calibration/bougnoux.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "varsfm/estimators/fundamental_8pt.h"
#include "varsfm/estimators/fundamental_refinement.h"
#include "varsfm/geometry/fundamental.h"
#include "varsfm/synthetic/synthetic_scene.h"

namespace varsfm {
namespace {

// A general two-view configuration: different focal lengths, optical axes that miss each other
// (look_at_jitter), a random arc.
SyntheticOptions GeneralPair(uint64_t seed, double noise) {
  Rng rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  SyntheticOptions o;
  o.num_images = 2;
  o.num_points = 400;
  o.arc_degrees = 20.0 + 40.0 * u(rng);
  o.focal_start = 700.0 + 400.0 * u(rng);
  o.focal_end = 900.0 + 700.0 * u(rng);
  o.look_at_jitter = 1.0;
  o.noise_sigma = noise;
  o.seed = seed;
  return o;
}

Eigen::Vector2d PrincipalPoint(const Camera& c) {
  return {c.params[Camera::kU0], c.params[Camera::kV0]};
}

double Percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(q * (v.size() - 1))];
}

TEST(Bougnoux, ExactOnNoiseFreeGeneralPairs) {
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    const SyntheticScene s = GenerateSyntheticScene(GeneralPair(seed, 0.0));
    const Eigen::Matrix3d F =
        FundamentalFromPose(s.cameras[0].K(), s.cameras[1].K(), s.poses[1] * s.poses[0].Inverse());
    const auto f =
        BougnouxFocalLengths(F, PrincipalPoint(s.cameras[0]), PrincipalPoint(s.cameras[1]));
    ASSERT_TRUE(f.has_value()) << "seed " << seed;
    EXPECT_NEAR(f->first / s.cameras[0].focal(), 1.0, 1e-6) << "seed " << seed;
    EXPECT_NEAR(f->second / s.cameras[1].focal(), 1.0, 1e-6) << "seed " << seed;
  }
}

// F estimated from 0.5 px noisy correspondences (normalised 8-point, then Sampson refinement)
// over 50 random general configurations.
TEST(Bougnoux, AccurateAtHalfPixelNoise) {
  std::vector<double> errors;
  int failures = 0;
  for (uint64_t seed = 100; seed < 150; ++seed) {
    const SyntheticScene s = GenerateSyntheticScene(GeneralPair(seed, 0.5));
    std::vector<Eigen::Vector2d> x1, x2;
    s.Correspondences(0, 1, &x1, &x2);
    Eigen::Matrix3d F;
    ASSERT_TRUE(Fundamental8pt(x1, x2, &F));
    F = RefineFundamentalMatrix(x1, x2, F);
    const auto f =
        BougnouxFocalLengths(F, PrincipalPoint(s.cameras[0]), PrincipalPoint(s.cameras[1]));
    if (!f) {
      ++failures;
      continue;
    }
    errors.push_back(std::abs(f->first / s.cameras[0].focal() - 1.0));
    errors.push_back(std::abs(f->second / s.cameras[1].focal() - 1.0));
  }
  const double median = Percentile(errors, 0.5), p90 = Percentile(errors, 0.9);
  std::printf(
      "Bougnoux at 0.5 px: median focal error %.3f %%, 90th percentile %.3f %%, "
      "%d of 50 without a solution\n",
      100 * median, 100 * p90, failures);
  EXPECT_LE(failures, 2);
  EXPECT_LE(median, 0.01);
}

TEST(Bougnoux, EqualFocalFromEssentialSingularValues) {
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    SyntheticOptions o = GeneralPair(seed, 0.0);
    o.focal_start = o.focal_end = 900.0 + 50.0 * seed;
    const SyntheticScene s = GenerateSyntheticScene(o);
    const Eigen::Matrix3d F =
        FundamentalFromPose(s.cameras[0].K(), s.cameras[1].K(), s.poses[1] * s.poses[0].Inverse());
    const auto f = EqualFocalLength(F, PrincipalPoint(s.cameras[0]), PrincipalPoint(s.cameras[1]),
                                    300.0, 5000.0);
    ASSERT_TRUE(f.has_value()) << "seed " << seed;
    EXPECT_NEAR(*f / o.focal_start, 1.0, 1e-4) << "seed " << seed;
  }
}

}  // namespace
}  // namespace varsfm
