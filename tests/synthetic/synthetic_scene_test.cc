#include "varsfm/synthetic/synthetic_scene.h"

#include <gtest/gtest.h>

namespace varsfm {
namespace {

TEST(SyntheticScene, ObservationsAreExactProjectionsInsideTheImage) {
  SyntheticOptions o;
  o.num_images = 6;
  o.num_points = 500;
  o.focal_start = 800;
  o.focal_end = 1280;  // x1.6 zoom sweep
  o.k1 = -0.05;
  const SyntheticScene scene = GenerateSyntheticScene(o);
  ASSERT_EQ(scene.NumImages(), 6);
  EXPECT_DOUBLE_EQ(scene.cameras.front().focal(), 800);
  EXPECT_DOUBLE_EQ(scene.cameras.back().focal(), 1280);
  for (int i = 0; i < scene.NumImages(); ++i) {
    EXPECT_GT(scene.observations[i].size(), 200u) << "image " << i;
    for (const auto& obs : scene.observations[i]) {
      const Eigen::Vector3d x = scene.poses[i] * scene.points[obs.point_id];
      EXPECT_GT(x.z(), 0);
      EXPECT_LT((scene.cameras[i].Project(x) - obs.true_pixel).norm(), 1e-9);
      EXPECT_EQ(obs.pixel, obs.true_pixel);  // no noise asked for
      EXPECT_GE(obs.pixel.x(), 0);
      EXPECT_LT(obs.pixel.x(), o.width);
    }
  }
}

TEST(SyntheticScene, NoiseOutliersAndSeed) {
  SyntheticOptions o;
  o.noise_sigma = 0.5;
  o.outlier_ratio = 0.3;
  const SyntheticScene a = GenerateSyntheticScene(o);
  const SyntheticScene b = GenerateSyntheticScene(o);
  double sum_sq = 0;
  int inliers = 0, outliers = 0;
  for (size_t k = 0; k < a.observations[0].size(); ++k) {
    const auto& obs = a.observations[0][k];
    EXPECT_EQ(obs.pixel, b.observations[0][k].pixel);  // same seed, same scene
    if (obs.outlier) {
      ++outliers;
    } else {
      ++inliers;
      sum_sq += (obs.pixel - obs.true_pixel).squaredNorm();
    }
  }
  const double rms_per_axis = std::sqrt(sum_sq / (2.0 * inliers));
  EXPECT_NEAR(rms_per_axis, 0.5, 0.05);
  EXPECT_NEAR(static_cast<double>(outliers) / (inliers + outliers), 0.3, 0.06);
}

TEST(SyntheticScene, PureRotationSharesOneCentreAndPlaneIsFlat) {
  SyntheticOptions o;
  o.path = SyntheticOptions::Path::kPureRotation;
  o.structure = SyntheticOptions::Structure::kPlane;
  const SyntheticScene scene = GenerateSyntheticScene(o);
  for (const auto& pose : scene.poses)
    EXPECT_LT((pose.Center() - scene.poses[0].Center()).norm(), 1e-9);
  for (const auto& p : scene.points) EXPECT_EQ(p.z(), 0.0);
  std::vector<Eigen::Vector2d> x1, x2;
  scene.Correspondences(0, 1, &x1, &x2);
  EXPECT_GT(x1.size(), 100u);
}

}  // namespace
}  // namespace varsfm
