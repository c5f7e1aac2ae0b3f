#include "varsfm/sfm/absolute_pose_refinement.h"

#include <gtest/gtest.h>

#include <cmath>

#include <ceres/ceres.h>

#include "varsfm/ba/analytic_reprojection_cost.h"
#include "varsfm/synthetic/synthetic_scene.h"

namespace varsfm {
namespace {

// One image of a zooming orbit (k1 -0.05): its 2D-3D correspondences, exact or with noise.
struct Correspondences {
  Camera camera;
  Rigid3d pose;
  std::vector<Eigen::Vector2d> x;
  std::vector<Eigen::Vector3d> X;
};

Correspondences ImageOfOrbit(double noise_sigma) {
  SyntheticOptions o;
  o.num_images = 5;
  o.num_points = 600;
  o.focal_start = 800;
  o.focal_end = 1280;
  o.k1 = -0.05;
  o.noise_sigma = noise_sigma;
  const SyntheticScene scene = GenerateSyntheticScene(o);
  const int image = 3;
  Correspondences c{scene.cameras[image], scene.poses[image], {}, {}};
  for (const auto& obs : scene.observations[image]) {
    c.x.push_back(obs.pixel);
    c.X.push_back(scene.points[obs.point_id]);
  }
  return c;
}

// The start a registration hands over: the pose a little off, the focal length 10 % off.
void Perturb(Camera* camera, Rigid3d* pose) {
  camera->focal() *= 1.1;
  pose->rotation = (pose->rotation * Eigen::Quaterniond(Eigen::AngleAxisd(
                                         0.02, Eigen::Vector3d(1, 2, 3).normalized())))
                       .normalized();
  pose->translation += Eigen::Vector3d(0.05, -0.03, 0.04);
}

AbsolutePoseRefinementOptions FocalAndPose() {
  AbsolutePoseRefinementOptions options;
  options.intrinsics.refine_focal = true;
  options.intrinsics.refine_aspect = options.intrinsics.refine_skew = false;
  options.intrinsics.refine_principal_point = false;
  options.intrinsics.refine_k1 = options.intrinsics.refine_k2 = false;
  return options;
}

double AngleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return a.angularDistance(b);
}

TEST(RefineAbsolutePose, RecoversExactPoseAndFocalLength) {
  const Correspondences c = ImageOfOrbit(/*noise_sigma=*/0.0);
  ASSERT_GT(c.x.size(), 100u);
  Camera camera = c.camera;
  Rigid3d pose = c.pose;
  Perturb(&camera, &pose);
  ASSERT_TRUE(RefineAbsolutePose(FocalAndPose(), c.x, c.X, &camera, &pose));
  EXPECT_NEAR(camera.focal(), c.camera.focal(), 1e-6 * c.camera.focal());
  EXPECT_LT(AngleBetween(pose.rotation, c.pose.rotation), 1e-7);
  EXPECT_LT((pose.Center() - c.pose.Center()).norm(), 1e-6);  // orbit radius 5
  // Held intrinsics keep their values bit for bit.
  for (const int i :
       {Camera::kAspect, Camera::kSkew, Camera::kU0, Camera::kV0, Camera::kK1, Camera::kK2})
    EXPECT_EQ(camera.params[i], c.camera.params[i]) << "parameter " << i;
}

TEST(RefineAbsolutePose, HeldCameraMovesOnlyThePose) {
  const Correspondences c = ImageOfOrbit(/*noise_sigma=*/0.0);
  Camera camera = c.camera;
  Rigid3d pose = c.pose;
  Camera unused = camera;
  Perturb(&unused, &pose);  // the pose only: the camera stays the true one
  AbsolutePoseRefinementOptions options = FocalAndPose();
  options.intrinsics.refine_focal = false;
  ASSERT_TRUE(RefineAbsolutePose(options, c.x, c.X, &camera, &pose));
  EXPECT_EQ(camera.params, c.camera.params);
  EXPECT_LT(AngleBetween(pose.rotation, c.pose.rotation), 1e-7);
  EXPECT_LT((pose.Center() - c.pose.Center()).norm(), 1e-6);  // orbit radius 5
}

// The same problem through a ceres::Problem (Levenberg-Marquardt, DENSE_QR): the reference the
// refinement was written against. Both reach the same minimum of the noisy problem.
TEST(RefineAbsolutePose, ReachesCeresMinimumOnNoisyCorrespondences) {
  const Correspondences c = ImageOfOrbit(/*noise_sigma=*/0.5);
  Camera start_camera = c.camera;
  Rigid3d start_pose = c.pose;
  Perturb(&start_camera, &start_pose);
  AbsolutePoseRefinementOptions options = FocalAndPose();
  options.intrinsics.refine_k1 = true;

  Camera camera = start_camera;
  Rigid3d pose = start_pose;
  ASSERT_TRUE(RefineAbsolutePose(options, c.x, c.X, &camera, &pose));

  Camera ceres_camera = start_camera;
  Rigid3d ceres_pose = start_pose;
  std::vector<Eigen::Vector3d> points = c.X;
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::CauchyLoss loss(options.loss_scale_px);
  double* q = ceres_pose.rotation.coeffs().data();
  double* t = ceres_pose.translation.data();
  for (size_t i = 0; i < points.size(); ++i) {
    problem.AddResidualBlock(new AnalyticReprojectionCost(c.x[i]), &loss,
                             ceres_camera.params.data(), q, t, points[i].data());
    problem.SetParameterBlockConstant(points[i].data());
  }
  problem.SetManifold(q, new ceres::EigenQuaternionManifold);
  problem.SetManifold(
      ceres_camera.params.data(),
      new ceres::SubsetManifold(Camera::kNumParams, {Camera::kAspect, Camera::kSkew, Camera::kU0,
                                                     Camera::kV0, Camera::kK2}));
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.function_tolerance = 1e-12;
  solver_options.max_num_iterations = 100;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable());
  ceres_pose.rotation.normalize();

  EXPECT_NEAR(camera.focal(), ceres_camera.focal(), 1e-4 * ceres_camera.focal());
  EXPECT_NEAR(camera.params[Camera::kK1], ceres_camera.params[Camera::kK1], 1e-4);
  EXPECT_LT(AngleBetween(pose.rotation, ceres_pose.rotation), 1e-6);
  EXPECT_LT((pose.Center() - ceres_pose.Center()).norm(), 1e-5);
  // And near the truth: 0.5 px noise on hundreds of points.
  EXPECT_NEAR(camera.focal(), c.camera.focal(), 0.01 * c.camera.focal());
}

TEST(RefineAbsolutePose, RejectsTooFewOrMismatchedCorrespondences) {
  const Correspondences c = ImageOfOrbit(/*noise_sigma=*/0.0);
  Camera camera = c.camera;
  Rigid3d pose = c.pose;
  const std::vector<Eigen::Vector2d> five(c.x.begin(), c.x.begin() + 5);
  const std::vector<Eigen::Vector3d> five_points(c.X.begin(), c.X.begin() + 5);
  EXPECT_FALSE(RefineAbsolutePose(FocalAndPose(), five, five_points, &camera, &pose));
  const std::vector<Eigen::Vector3d> six_points(c.X.begin(), c.X.begin() + 6);
  EXPECT_FALSE(RefineAbsolutePose(FocalAndPose(), five, six_points, &camera, &pose));
}

}  // namespace
}  // namespace varsfm
