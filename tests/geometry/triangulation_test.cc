#include "varsfm/geometry/triangulation.h"

#include <numbers>

#include <gtest/gtest.h>

#include "varsfm/synthetic/synthetic_scene.h"

namespace varsfm {
namespace {

TEST(Triangulation, LinearIsExactWithoutNoise) {
  SyntheticOptions o;
  o.num_images = 4;
  o.focal_start = 700;
  o.focal_end = 2000;
  const SyntheticScene scene = GenerateSyntheticScene(o);
  std::vector<Eigen::Vector2d> x1, x2;
  std::vector<int> ids;
  scene.Correspondences(0, 3, &x1, &x2, &ids);
  ASSERT_GT(ids.size(), 100u);
  for (size_t i = 0; i < ids.size(); ++i) {
    Eigen::Vector3d X;
    ASSERT_TRUE(
        TriangulatePoint(scene.ProjectionMatrix(0), scene.ProjectionMatrix(3), x1[i], x2[i], &X));
    EXPECT_LT((X - scene.points[ids[i]]).norm(), 1e-8);
    EXPECT_TRUE(HasPositiveDepth(scene.poses[0], X));
    EXPECT_GT(ProjectionDepth(-2.0 * scene.ProjectionMatrix(3), X), 0.0);
  }
  // Multi-view, in normalised coordinates with [R | t].
  const int p = scene.observations[1][0].point_id;
  std::vector<Matrix34d> Ps;
  std::vector<Eigen::Vector2d> xs;
  for (int i = 0; i < scene.NumImages(); ++i) {
    for (const auto& obs : scene.observations[i]) {
      if (obs.point_id != p) continue;
      Ps.push_back(scene.poses[i].ToMatrix());
      xs.push_back(scene.cameras[i].ImageToNormalized(obs.pixel));
    }
  }
  ASSERT_GE(Ps.size(), 2u);
  Eigen::Vector3d X;
  ASSERT_TRUE(TriangulateMultiView(Ps, xs, &X));
  EXPECT_LT((X - scene.points[p]).norm(), 1e-9);
}

TEST(Triangulation, RefinementReducesReprojectionErrorWithDistortionAndNoise) {
  SyntheticOptions o;
  o.num_images = 5;
  o.num_points = 300;
  o.k1 = -0.15;
  o.k2 = 0.05;
  o.noise_sigma = 1.0;
  o.focal_start = 900;
  o.focal_end = 1500;
  const SyntheticScene scene = GenerateSyntheticScene(o);
  int refined_better = 0, total = 0;
  for (int p = 0; p < o.num_points; ++p) {
    std::vector<Camera> cams;
    std::vector<Rigid3d> poses;
    std::vector<Eigen::Vector2d> pixels, normalized;
    std::vector<Matrix34d> Ps;
    for (int i = 0; i < scene.NumImages(); ++i) {
      for (const auto& obs : scene.observations[i]) {
        if (obs.point_id != p) continue;
        cams.push_back(scene.cameras[i]);
        poses.push_back(scene.poses[i]);
        pixels.push_back(obs.pixel);
        normalized.push_back(scene.cameras[i].ImageToNormalized(obs.pixel));
        Ps.push_back(scene.poses[i].ToMatrix());
      }
    }
    if (cams.size() < 3) continue;
    Eigen::Vector3d X;
    ASSERT_TRUE(TriangulateMultiView(Ps, normalized, &X));
    const auto cost = [&](const Eigen::Vector3d& Y) {
      double c = 0;
      for (size_t k = 0; k < cams.size(); ++k) {
        const double e = ReprojectionError(cams[k], poses[k], pixels[k], Y);
        c += e * e;
      }
      return c;
    };
    const double before = cost(X);
    Eigen::Vector3d Y = X;
    ASSERT_TRUE(RefineTriangulatedPoint(cams, poses, pixels, &Y));
    const double after = cost(Y);
    EXPECT_LE(after, before + 1e-9);
    refined_better += after < before;
    ++total;
    // Also stationary: the true point is not better than the refined one.
    EXPECT_LE(after, cost(scene.points[p]) + 1e-9);
  }
  ASSERT_GT(total, 100);
  EXPECT_GT(refined_better, total * 9 / 10);
}

TEST(Triangulation, AngleAndCheirality) {
  const Eigen::Vector3d c1(0, 0, 0), c2(2, 0, 0), X(1, 0, 1);
  EXPECT_NEAR(TriangulationAngle(c1, c2, X), std::numbers::pi / 2, 1e-12);
  EXPECT_NEAR(TriangulationAngle(c1, c1, X), 0.0, 1e-12);
  const Rigid3d identity;
  EXPECT_TRUE(HasPositiveDepth(identity, X));
  EXPECT_FALSE(HasPositiveDepth(identity, -X));
  EXPECT_LT(ProjectionDepth(Matrix34d::Identity(), -X), 0.0);
}

}  // namespace
}  // namespace varsfm
