#include "varsfm/estimators/p3p.h"

#include <random>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "varsfm/estimators/absolute_pose_estimator.h"
#include "varsfm/synthetic/synthetic_scene.h"

namespace varsfm {
namespace {

// Distance between two poses: rotation (Frobenius norm of the difference of the matrices) and
// translation, the larger of the two.
double PoseDistance(const Rigid3d& a, const Rigid3d& b) {
  return std::max((a.R() - b.R()).norm(), (a.translation - b.translation).norm());
}

struct P3PProblem {
  Rigid3d truth;
  std::array<Eigen::Vector3d, 3> bearings, points;
};

// Three points in front of a random camera (depth 2 to 10, within a 90 degree field of view),
// their exact bearings, and the world points through a random pose.
P3PProblem RandomProblem(std::mt19937* rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0), depth(2.0, 10.0);
  P3PProblem p;
  p.truth = Rigid3d(Eigen::Quaterniond(unit(*rng), unit(*rng), unit(*rng), unit(*rng)).normalized(),
                    Eigen::Vector3d(unit(*rng), unit(*rng), unit(*rng)) * 3.0);
  for (int k = 0; k < 3; ++k) {
    const double z = depth(*rng);
    const Eigen::Vector3d camera_point(unit(*rng) * z, unit(*rng) * z, z);
    p.bearings[k] = camera_point.normalized();
    p.points[k] = p.truth.Inverse() * camera_point;
  }
  return p;
}

TEST(SolveP3P, NoiseFreeRecoversThePoseAndEverySolutionFits) {
  std::mt19937 rng(42);
  constexpr int kTrials = 2000;
  for (int trial = 0; trial < kTrials; ++trial) {
    const P3PProblem p = RandomProblem(&rng);
    std::vector<Rigid3d> poses;
    const int n = SolveP3P(p.bearings, p.points, &poses);
    ASSERT_EQ(n, static_cast<int>(poses.size()));
    ASSERT_GE(n, 1) << "trial " << trial;
    ASSERT_LE(n, 4);
    double best = std::numeric_limits<double>::infinity();
    for (const Rigid3d& pose : poses) {
      best = std::min(best, PoseDistance(pose, p.truth));
      // Each solution puts every point on its ray, in front of the camera.
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d x = pose * p.points[k];
        EXPECT_GT(x.z(), 0);
        EXPECT_LT((x.normalized() - p.bearings[k]).norm(), 1e-9) << "trial " << trial;
      }
    }
    EXPECT_LT(best, 1e-9) << "trial " << trial;
  }
}

TEST(SolveP3P, UnnormalisedBearingsGiveTheSamePoses) {
  std::mt19937 rng(7);
  const P3PProblem p = RandomProblem(&rng);
  std::array<Eigen::Vector3d, 3> scaled = p.bearings;
  for (int k = 0; k < 3; ++k) scaled[k] *= 0.5 + k;
  std::vector<Rigid3d> a, b;
  ASSERT_EQ(SolveP3P(p.bearings, p.points, &a), SolveP3P(scaled, p.points, &b));
  for (size_t k = 0; k < a.size(); ++k) EXPECT_LT(PoseDistance(a[k], b[k]), 1e-12);
}

TEST(SolveP3P, DegenerateSamplesGiveNoPose) {
  std::vector<Rigid3d> poses;
  const std::array<Eigen::Vector3d, 3> bearings = {
      Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0.1, 0, 1), Eigen::Vector3d(0, 0.1, 1)};
  // Collinear world points leave the rotation about their line free.
  EXPECT_EQ(SolveP3P(bearings,
                     {Eigen::Vector3d(0, 0, 5), Eigen::Vector3d(1, 0, 5), Eigen::Vector3d(2, 0, 5)},
                     &poses),
            0);
  // Coincident points.
  EXPECT_EQ(SolveP3P(bearings,
                     {Eigen::Vector3d(0, 0, 5), Eigen::Vector3d(0, 0, 5), Eigen::Vector3d(1, 0, 5)},
                     &poses),
            0);
  // A zero bearing.
  EXPECT_EQ(SolveP3P({Eigen::Vector3d::Zero(), bearings[1], bearings[2]},
                     {Eigen::Vector3d(0, 0, 5), Eigen::Vector3d(1, 0, 5), Eigen::Vector3d(0, 1, 5)},
                     &poses),
            0);
  EXPECT_TRUE(poses.empty());
}

// The observations of one image of a synthetic scene in normalised coordinates, with the 3D
// points and the outlier flags.
struct PoseData {
  std::vector<Eigen::Vector2d> x;
  std::vector<Eigen::Vector3d> X;
  std::vector<char> outlier;
};

PoseData Collect(const SyntheticScene& scene, int image) {
  PoseData d;
  for (const auto& obs : scene.observations[image]) {
    d.x.push_back(scene.cameras[image].ImageToNormalized(obs.pixel));
    d.X.push_back(scene.points[obs.point_id]);
    d.outlier.push_back(obs.outlier);
  }
  return d;
}

// Three images of a box of points, focal length 800 to 1600 px.
SyntheticScene PoseScene(int num_points, double noise_sigma, double outlier_ratio) {
  return GenerateSyntheticScene({.num_images = 3,
                                 .num_points = num_points,
                                 .focal_start = 800,
                                 .focal_end = 1600,
                                 .noise_sigma = noise_sigma,
                                 .outlier_ratio = outlier_ratio});
}

TEST(AbsolutePoseEstimator, NonMinimalSolveConvergesFromAPerturbedPose) {
  const SyntheticScene scene = PoseScene(300, 0, 0);
  const PoseData d = Collect(scene, 1);
  const AbsolutePoseEstimator estimator{d.x, d.X};
  std::vector<int> all(d.x.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  const Rigid3d& truth = scene.poses[1];
  const Rigid3d start(
      (Eigen::Quaterniond(Eigen::AngleAxisd(0.05, Eigen::Vector3d(1, 2, 3).normalized())) *
       truth.rotation)
          .normalized(),
      truth.translation + Eigen::Vector3d(0.1, -0.05, 0.2));
  std::vector<Rigid3d> models;
  estimator.NonMinimalSolve(all, start, &models);
  ASSERT_EQ(models.size(), 1u);
  EXPECT_LT(PoseDistance(models[0], truth), 1e-9);
  // Fewer than three points do not determine a pose.
  models.clear();
  estimator.NonMinimalSolve({0, 1}, start, &models);
  EXPECT_TRUE(models.empty());
}

TEST(AbsolutePoseRansac, RecoversTheExactPoseAmongHalfOutliers) {
  const SyntheticScene scene = PoseScene(600, 0, 0.5);
  for (int image = 0; image < scene.NumImages(); ++image) {
    const PoseData d = Collect(scene, image);
    RansacOptions options;
    options.max_error = scene.cameras[image].ImageToNormalizedThreshold(2.0);
    const auto report = Ransac(AbsolutePoseEstimator{d.x, d.X}, options);
    ASSERT_TRUE(report.success);
    // Noise-free inliers: the refined pose is the true one.
    EXPECT_LT(PoseDistance(report.model, scene.poses[image]), 1e-9) << image;
    int true_positives = 0, false_positives = 0, false_negatives = 0;
    for (size_t i = 0; i < d.x.size(); ++i) {
      true_positives += report.inlier_mask[i] && !d.outlier[i];
      false_positives += report.inlier_mask[i] && d.outlier[i];
      false_negatives += !report.inlier_mask[i] && !d.outlier[i];
    }
    EXPECT_EQ(false_negatives, 0);
    // A random pixel lands within 2 px of its point's projection with probability ~1e-5.
    EXPECT_LE(false_positives, 2);
    EXPECT_GT(true_positives, 100);
  }
}

TEST(AbsolutePoseRansac, NoisyDataAndTheSameSeedGivesTheSameBits) {
  const SyntheticScene scene = PoseScene(500, 0.5, 0.3);
  const PoseData d = Collect(scene, 1);
  RansacOptions options;
  options.max_error = scene.cameras[1].ImageToNormalizedThreshold(2.0);
  options.seed = 99;
  const auto a = Ransac(AbsolutePoseEstimator{d.x, d.X}, options);
  const auto b = Ransac(AbsolutePoseEstimator{d.x, d.X}, options);
  ASSERT_TRUE(a.success);
  EXPECT_EQ(a.model.rotation.coeffs(), b.model.rotation.coeffs());
  EXPECT_EQ(a.model.translation, b.model.translation);
  EXPECT_EQ(a.inlier_mask, b.inlier_mask);
  // 0.5 px noise at f = 1200 on a scene 5 units away: the pose within a milliradian.
  EXPECT_LT((a.model.R() - scene.poses[1].R()).norm(), 1e-3);
  EXPECT_LT((a.model.Center() - scene.poses[1].Center()).norm(), 5e-3);
}

}  // namespace
}  // namespace varsfm
