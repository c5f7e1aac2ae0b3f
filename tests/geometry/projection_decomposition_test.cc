#include "varsfm/geometry/projection_decomposition.h"

#include <gtest/gtest.h>

#include "varsfm/synthetic/synthetic_scene.h"

namespace varsfm {
namespace {

SyntheticScene ZoomScene() {
  SyntheticOptions o;
  o.num_images = 5;
  o.focal_start = 800;
  o.focal_end = 2400;
  o.aspect = 1.05;
  o.skew = 0.7;
  o.principal_point_offset = 30;
  return GenerateSyntheticScene(o);
}

TEST(RQDecomposition, RoundTrips) {
  const SyntheticScene scene = ZoomScene();
  for (int i = 0; i < scene.NumImages(); ++i) {
    // Both signs of M: the decomposition must still give a positive diagonal.
    for (const double sign : {1.0, -1.0}) {
      const Eigen::Matrix3d M = sign * 3.7 * scene.ProjectionMatrix(i).leftCols<3>();
      Eigen::Matrix3d K, R;
      ASSERT_TRUE(RQDecomposition(M, &K, &R));
      EXPECT_NEAR(K(1, 0), 0.0, 1e-12);
      EXPECT_NEAR(K(2, 0), 0.0, 1e-12);
      EXPECT_NEAR(K(2, 1), 0.0, 1e-12);
      for (int d = 0; d < 3; ++d) EXPECT_GT(K(d, d), 0.0);
      EXPECT_LT((R * R.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
      EXPECT_NEAR(R.determinant(), sign, 1e-12);
      EXPECT_LT((K * R - M).norm(), 1e-12 * M.norm());
    }
  }
}

TEST(DecomposeProjectionMatrix, RecoversSyntheticCamera) {
  const SyntheticScene scene = ZoomScene();
  for (int i = 0; i < scene.NumImages(); ++i) {
    for (const double scale : {2.5e-3, -17.0}) {
      const Matrix34d P = scale * scene.ProjectionMatrix(i);
      Eigen::Matrix3d K, R;
      Eigen::Vector3d t;
      ASSERT_TRUE(DecomposeProjectionMatrix(P, &K, &R, &t));
      const Eigen::Matrix3d K_true = scene.cameras[i].K();
      EXPECT_NEAR(K(0, 0) / K_true(0, 0), 1.0, 1e-6);
      EXPECT_NEAR(K(1, 1) / K_true(1, 1), 1.0, 1e-6);
      EXPECT_LT((K - K_true).norm(), 1e-6 * K_true.norm());
      EXPECT_DOUBLE_EQ(K(2, 2), 1.0);
      EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
      EXPECT_LT((R - scene.poses[i].R()).norm(), 1e-9);
      EXPECT_LT((t - scene.poses[i].translation).norm(), 1e-9);
    }
  }
}

TEST(RQDecomposition, RejectsSingular) {
  Eigen::Matrix3d K, R;
  EXPECT_FALSE(RQDecomposition(Eigen::Matrix3d::Zero(), &K, &R));
}

}  // namespace
}  // namespace varsfm
