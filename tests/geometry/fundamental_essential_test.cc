#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "varsfm/geometry/essential.h"
#include "varsfm/geometry/fundamental.h"
#include "varsfm/synthetic/synthetic_scene.h"

namespace varsfm {
namespace {

SyntheticScene Scene() {
  SyntheticOptions o;
  o.num_images = 4;
  o.focal_start = 900;
  o.focal_end = 1800;
  o.principal_point_offset = 20;
  return GenerateSyntheticScene(o);
}

Rigid3d Relative(const SyntheticScene& s, int i, int j) {
  return s.poses[j] * s.poses[i].Inverse();
}

TEST(Fundamental, FromProjectionsAndFromPoseAgreeAndAreExact) {
  const SyntheticScene scene = Scene();
  const Eigen::Matrix3d Fp =
      FundamentalFromProjections(scene.ProjectionMatrix(0), scene.ProjectionMatrix(3));
  Eigen::Matrix3d Fk =
      FundamentalFromPose(scene.cameras[0].K(), scene.cameras[3].K(), Relative(scene, 0, 3));
  if (Fk.cwiseProduct(Fp).sum() < 0) Fk = -Fk;
  EXPECT_LT((Fp - Fk).norm(), 1e-9);
  std::vector<Eigen::Vector2d> x1, x2;
  scene.Correspondences(0, 3, &x1, &x2);
  ASSERT_GT(x1.size(), 100u);
  for (size_t i = 0; i < x1.size(); ++i) EXPECT_LT(SampsonError(Fp, x1[i], x2[i]), 1e-8);

  Eigen::Vector3d e1, e2;
  Epipoles(Fp, &e1, &e2);
  EXPECT_LT((Fp * e1).norm(), 1e-12);
  EXPECT_LT((Fp.transpose() * e2).norm(), 1e-12);
  // e2 is the image of camera 1's centre in image 2.
  const Eigen::Vector3d c1 = scene.ProjectionMatrix(3) * scene.poses[0].Center().homogeneous();
  EXPECT_LT(c1.normalized().cross(e2).norm(), 1e-9);
}

// Points in front of both cameras agree on the orientation of their epipolar lines; a point
// behind the second camera, though it satisfies x2^T F x1 = 0, does not (Chum, Werner & Matas
// 2004).
TEST(Fundamental, OrientedConstraintRejectsAPointBehindACamera) {
  Eigen::Matrix3d K;
  K << 800, 0, 320, 0, 800, 240, 0, 0, 1;
  Rigid3d cam2_from_cam1;
  cam2_from_cam1.rotation = Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY());
  cam2_from_cam1.translation = Eigen::Vector3d(-1.0, 0.1, -4.0);  // 4 units ahead of camera 1
  for (const double sign : {1.0, -1.0}) {  // F is known up to sign: either must do
    const Eigen::Matrix3d F = sign * FundamentalFromPose(K, K, cam2_from_cam1);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<Eigen::Vector2d> x1, x2;
    for (int i = 0; i < 20; ++i) {  // depth 6 to 10 from camera 1: in front of both
      const Eigen::Vector3d X(2 * u(rng), 2 * u(rng), 8 + 2 * u(rng));
      x1.push_back((K * X).hnormalized());
      x2.push_back((K * (cam2_from_cam1 * X)).hnormalized());
    }
    EXPECT_TRUE(SatisfiesOrientedEpipolarConstraint(F, x1, x2));
    // Depth 2 from camera 1, about -2 from camera 2: behind it, projected all the same.
    const Eigen::Vector3d behind(0.3, -0.2, 2.0);
    ASSERT_LT((cam2_from_cam1 * behind).z(), 0);
    x1.push_back((K * behind).hnormalized());
    x2.push_back((K * (cam2_from_cam1 * behind)).hnormalized());
    EXPECT_LT(SampsonError(F, x1.back(), x2.back()), 1e-9);
    EXPECT_FALSE(SatisfiesOrientedEpipolarConstraint(F, x1, x2));
  }
}

// The scalar form in fundamental.h claims the sums of the textbook form in the same order: the
// same doubles, to the bit (the mapper's models depend on it).
TEST(Fundamental, SampsonErrorSquaredIsTheMatrixFormToTheBit) {
  std::mt19937 rng(7);
  std::normal_distribution<double> entry(0, 1);
  std::uniform_real_distribution<double> pixel(0, 3000);
  for (int trial = 0; trial < 20000; ++trial) {
    Eigen::Matrix3d F;
    for (int i = 0; i < 9; ++i) F(i) = entry(rng) * std::pow(10.0, -(i % 4));
    const Eigen::Vector2d x1(pixel(rng), pixel(rng)), x2(pixel(rng), pixel(rng));
    const Eigen::Vector3d Fx1 = F * x1.homogeneous();
    const Eigen::Vector3d Ftx2 = F.transpose() * x2.homogeneous();
    const double e = x2.homogeneous().dot(Fx1);
    const double d = Fx1.head<2>().squaredNorm() + Ftx2.head<2>().squaredNorm();
    ASSERT_EQ(SampsonErrorSquared(F, x1, x2), e * e / d) << trial;
  }
  EXPECT_EQ(SampsonErrorSquared(Eigen::Matrix3d::Zero(), {1, 2}, {3, 4}), 0.0);
}

TEST(Fundamental, SampsonErrorMatchesOffsetForSmallPerturbation) {
  const SyntheticScene scene = Scene();
  const Eigen::Matrix3d F =
      FundamentalFromProjections(scene.ProjectionMatrix(0), scene.ProjectionMatrix(1));
  std::vector<Eigen::Vector2d> x1, x2;
  scene.Correspondences(0, 1, &x1, &x2);
  // Moving x2 by d along the epipolar line normal gives a Sampson distance <= d (it
  // distributes the error over both images) and > 0.
  const Eigen::Vector3d l = F * x1[0].homogeneous();
  const Eigen::Vector2d n = l.head<2>().normalized();
  const double e = SampsonError(F, x1[0], x2[0] + 0.5 * n);
  EXPECT_GT(e, 0.1);
  EXPECT_LE(e, 0.5 + 1e-9);
}

TEST(Essential, DecompositionContainsTruePoseAndCheiralityPicksIt) {
  const SyntheticScene scene = Scene();
  const Rigid3d truth = Relative(scene, 0, 2);
  const Eigen::Matrix3d E = EssentialFromPose(truth);
  std::vector<Eigen::Vector2d> p1, p2, x1, x2;
  scene.Correspondences(0, 2, &p1, &p2);
  for (size_t i = 0; i < p1.size(); ++i) {
    x1.push_back(scene.cameras[0].ImageToNormalized(p1[i]));
    x2.push_back(scene.cameras[2].ImageToNormalized(p2[i]));
  }
  const std::vector<Rigid3d> poses = PosesFromEssentialMatrix(E);
  ASSERT_EQ(poses.size(), 4u);
  for (const Rigid3d& pose : poses) {
    EXPECT_NEAR(pose.R().determinant(), 1.0, 1e-12);
    EXPECT_NEAR(pose.translation.norm(), 1.0, 1e-12);
  }
  Rigid3d pose;
  std::vector<char> mask;
  const int count = PoseFromEssentialMatrix(E, x1, x2, &pose, &mask);
  EXPECT_EQ(count, static_cast<int>(x1.size()));
  EXPECT_LT((pose.R() - truth.R()).norm(), 1e-9);
  EXPECT_LT((pose.translation - truth.translation.normalized()).norm(), 1e-9);
  EXPECT_EQ(mask.size(), x1.size());

  // The closest essential matrix of a perturbed E has two equal singular values.
  const Eigen::Matrix3d Ep = ProjectToEssential(E + 1e-3 * Eigen::Matrix3d::Ones());
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(Ep);
  EXPECT_NEAR(svd.singularValues()[0], svd.singularValues()[1], 1e-12);
  EXPECT_NEAR(svd.singularValues()[2], 0.0, 1e-12);
}

}  // namespace
}  // namespace varsfm
