#include "varsfm/eval/alignment.h"

#include <gtest/gtest.h>

#include <random>

namespace varsfm {
namespace {

Sim3d KnownSimilarity() {
  Sim3d sim;
  sim.scale = 2.5;
  sim.rotation =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  sim.translation = Eigen::Vector3d(3, -1, 10);
  return sim;
}

std::vector<Eigen::Vector3d> RandomPoints(int n, uint64_t seed) {
  Rng rng(seed);
  std::uniform_real_distribution<double> u(-5, 5);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < n; ++i) points.emplace_back(u(rng), u(rng), u(rng));
  return points;
}

TEST(Alignment, RecoversAKnownSimilarityExactly) {
  const Sim3d truth = KnownSimilarity();
  const auto source = RandomPoints(12, 1);
  std::vector<Eigen::Vector3d> target;
  for (const auto& x : source) target.push_back(truth * x);
  const AlignmentResult r = AlignSimilarity(source, target);
  ASSERT_TRUE(r.success);
  EXPECT_NEAR(r.sim.scale, truth.scale, 1e-12);
  EXPECT_LT((r.sim.rotation - truth.rotation).norm(), 1e-12);
  EXPECT_LT((r.sim.translation - truth.translation).norm(), 1e-11);
  EXPECT_EQ(r.num_inliers, 12u);
  const Sim3d identity_check = r.sim.Inverse();
  EXPECT_LT((identity_check * target[3] - source[3]).norm(), 1e-12);
}

TEST(Alignment, RobustAlignmentIgnoresOutlierPoints) {
  const Sim3d truth = KnownSimilarity();
  const auto source = RandomPoints(11, 2);
  std::vector<Eigen::Vector3d> target;
  for (const auto& x : source) target.push_back(truth * x);
  target[2] += Eigen::Vector3d(4, 0, 0);  // two badly placed cameras
  target[7] += Eigen::Vector3d(0, -3, 1);
  const AlignmentResult plain = AlignSimilarity(source, target);
  ASSERT_TRUE(plain.success);
  EXPECT_GT(std::abs(plain.sim.scale - truth.scale), 1e-3);  // least squares is dragged
  const AlignmentResult robust = AlignSimilarity(source, target, {.inlier_threshold = 0.1});
  ASSERT_TRUE(robust.success);
  EXPECT_EQ(robust.num_inliers, 9u);
  EXPECT_FALSE(robust.inliers[2]);
  EXPECT_FALSE(robust.inliers[7]);
  EXPECT_NEAR(robust.sim.scale, truth.scale, 1e-12);
  EXPECT_LT((robust.sim.translation - truth.translation).norm(), 1e-10);
}

TEST(Alignment, FailsOnTooFewOrCollinearPoints) {
  const std::vector<Eigen::Vector3d> two = {{0, 0, 0}, {1, 0, 0}};
  EXPECT_FALSE(AlignSimilarity(two, two).success);
  const std::vector<Eigen::Vector3d> line = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {5, 5, 5}};
  EXPECT_FALSE(AlignSimilarity(line, line).success);
}

}  // namespace
}  // namespace varsfm
