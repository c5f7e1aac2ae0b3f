#include <gtest/gtest.h>

#include "varsfm/estimators/projection_dlt.h"
#include "varsfm/estimators/projection_estimator.h"
#include "varsfm/estimators/ransac.h"
#include "varsfm/geometry/projection_decomposition.h"
#include "varsfm/synthetic/synthetic_scene.h"

namespace varsfm {
namespace {

SyntheticOptions Options() {
  SyntheticOptions o;
  o.num_images = 3;
  o.num_points = 1500;
  o.focal_start = 700;
  o.focal_end = 2200;
  o.aspect = 1.02;
  o.principal_point_offset = 30;
  return o;
}

void Collect(const SyntheticScene& s, int image, std::vector<Eigen::Vector2d>* x,
             std::vector<Eigen::Vector3d>* X, std::vector<char>* outlier) {
  for (const auto& obs : s.observations[image]) {
    x->push_back(obs.pixel);
    X->push_back(s.points[obs.point_id]);
    outlier->push_back(obs.outlier);
  }
}

TEST(ProjectionDLT, ExactAndDecomposes) {
  const SyntheticScene scene = GenerateSyntheticScene(Options());
  for (int image = 0; image < scene.NumImages(); ++image) {
    std::vector<Eigen::Vector2d> x;
    std::vector<Eigen::Vector3d> X;
    std::vector<char> outlier;
    Collect(scene, image, &x, &X, &outlier);
    for (const size_t n : {size_t{6}, x.size()}) {
      Matrix34d P;
      ASSERT_TRUE(ProjectionDLT({x.begin(), x.begin() + n}, {X.begin(), X.begin() + n}, &P));
      Matrix34d P_true = scene.ProjectionMatrix(image);
      P_true /= P_true.norm();
      EXPECT_LT((P / P.norm() - P_true).norm(), 1e-8) << n;
      Eigen::Matrix3d K, R;
      Eigen::Vector3d t;
      ASSERT_TRUE(DecomposeProjectionMatrix(P, &K, &R, &t));
      EXPECT_NEAR(K(0, 0) / scene.cameras[image].focal(), 1.0, 1e-6);
      EXPECT_LT((R - scene.poses[image].R()).norm(), 1e-6);
      // Depth convention: the third row gives the camera-frame depth.
      EXPECT_NEAR(P.row(2).dot(X[0].homogeneous()), (scene.poses[image] * X[0]).z(), 1e-8);
    }
  }
}

TEST(EstimateProjectionMatrix, RobustToOutliersAndDeterministic) {
  SyntheticOptions o = Options();
  o.noise_sigma = 0.5;
  o.outlier_ratio = 0.5;
  const SyntheticScene scene = GenerateSyntheticScene(o);
  std::vector<Eigen::Vector2d> x;
  std::vector<Eigen::Vector3d> X;
  std::vector<char> outlier;
  Collect(scene, 1, &x, &X, &outlier);
  RansacOptions options;
  options.max_error = 2.0;
  const auto report = EstimateProjectionMatrix(x, X, options);
  ASSERT_TRUE(report.success);
  int tp = 0, fp = 0, fn = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    tp += report.inlier_mask[i] && !outlier[i];
    fp += report.inlier_mask[i] && outlier[i];
    fn += !report.inlier_mask[i] && !outlier[i];
  }
  EXPECT_GT(tp / double(tp + fn), 0.95);
  EXPECT_GT(tp / double(tp + fp), 0.95);
  Eigen::Matrix3d K, R;
  Eigen::Vector3d t;
  ASSERT_TRUE(DecomposeProjectionMatrix(report.model, &K, &R, &t));
  EXPECT_NEAR(K(0, 0) / scene.cameras[1].focal(), 1.0, 0.02);
  const auto again = EstimateProjectionMatrix(x, X, options);
  EXPECT_EQ(again.model, report.model);
  EXPECT_EQ(again.inlier_mask, report.inlier_mask);
  RansacOptions other = options;
  other.seed = 7;
  EXPECT_TRUE(EstimateProjectionMatrix(x, X, other).success);
}

TEST(Ransac, IterationCountFollowsInlierRatio) {
  using ransac_internal::RequiredIterations;
  EXPECT_EQ(RequiredIterations(100, 100, 7, 0.9999, 100, 10000), 100);
  // w = 0.5, s = 7: log(1e-4) / log(1 - 1/128) = 1174.3.
  EXPECT_EQ(RequiredIterations(50, 100, 7, 0.9999, 100, 10000), 1175);
  EXPECT_EQ(RequiredIterations(1, 100, 7, 0.9999, 100, 10000), 10000);
}

TEST(Ransac, FailsWithTooFewData) {
  const std::vector<Eigen::Vector2d> x(5, Eigen::Vector2d::Zero());
  const std::vector<Eigen::Vector3d> X(5, Eigen::Vector3d::Ones());
  EXPECT_FALSE(EstimateProjectionMatrix(x, X, RansacOptions{}).success);
}

}  // namespace
}  // namespace varsfm
