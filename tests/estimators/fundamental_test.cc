#include <algorithm>

#include <gtest/gtest.h>

#include "estimators/test_scenes.h"
#include "varsfm/estimators/fundamental_7pt.h"
#include "varsfm/estimators/fundamental_8pt.h"
#include "varsfm/estimators/fundamental_refinement.h"
#include "varsfm/estimators/two_view_estimators.h"
#include "varsfm/geometry/fundamental.h"

namespace varsfm {
namespace {

double MaxSampson(const Eigen::Matrix3d& F, const testing::Matches& m) {
  double worst = 0;
  for (size_t i = 0; i < m.x1.size(); ++i)
    if (!m.outlier[i]) worst = std::max(worst, SampsonError(F, m.x1[i], m.x2[i]));
  return worst;
}

TEST(Fundamental7pt, OneSolutionIsExact) {
  const SyntheticScene scene = GenerateSyntheticScene(testing::ZoomBox());
  const testing::Matches m = testing::PairMatches(scene, 0, 2);
  for (int start = 0; start + 7 <= 70; start += 7) {
    const std::vector<Eigen::Vector2d> y1(m.x1.begin() + start, m.x1.begin() + start + 7);
    const std::vector<Eigen::Vector2d> y2(m.x2.begin() + start, m.x2.begin() + start + 7);
    std::vector<Eigen::Matrix3d> models;
    ASSERT_GE(Fundamental7pt(y1, y2, &models), 1);
    double best = 1e300;
    for (const auto& F : models) best = std::min(best, MaxSampson(F, m));
    EXPECT_LT(best, 1e-8);
  }
}

// The estimator's minimal solve keeps the seven-point solutions whose sample agrees on the
// orientation of its epipolar lines, the exact one among them.
TEST(FundamentalEstimator, MinimalSolveKeepsTheOrientedSolutions) {
  const SyntheticScene scene = GenerateSyntheticScene(testing::ZoomBox());
  const testing::Matches m = testing::PairMatches(scene, 0, 2);
  const FundamentalEstimator estimator{m.x1, m.x2};
  int dropped = 0;
  for (int start = 0; start + 7 <= 140; start += 7) {
    std::vector<int> sample(7);
    for (int k = 0; k < 7; ++k) sample[k] = start + k;
    if (std::any_of(sample.begin(), sample.end(), [&](int i) { return m.outlier[i]; })) continue;
    const std::vector<Eigen::Vector2d> y1(m.x1.begin() + start, m.x1.begin() + start + 7);
    const std::vector<Eigen::Vector2d> y2(m.x2.begin() + start, m.x2.begin() + start + 7);
    std::vector<Eigen::Matrix3d> all, kept;
    Fundamental7pt(y1, y2, &all);
    estimator.MinimalSolve(sample, &kept);
    double best = 1e300;
    for (const auto& F : kept) {
      EXPECT_TRUE(SatisfiesOrientedEpipolarConstraint(F, y1, y2));
      best = std::min(best, MaxSampson(F, m));
    }
    EXPECT_LT(best, 1e-8);
    dropped += static_cast<int>(all.size() - kept.size());
  }
  RecordProperty("dropped", dropped);
}

TEST(Fundamental8pt, ExactWithoutNoise) {
  const SyntheticScene scene = GenerateSyntheticScene(testing::ZoomBox());
  const testing::Matches m = testing::PairMatches(scene, 0, 1);
  for (const size_t n : {size_t{8}, size_t{50}, m.x1.size()}) {
    const std::vector<Eigen::Vector2d> y1(m.x1.begin(), m.x1.begin() + n);
    const std::vector<Eigen::Vector2d> y2(m.x2.begin(), m.x2.begin() + n);
    Eigen::Matrix3d F;
    ASSERT_TRUE(Fundamental8pt(y1, y2, &F));
    EXPECT_LT(MaxSampson(F, m), 1e-8) << n;
    EXPECT_NEAR(F.determinant(), 0.0, 1e-12);
  }
}

TEST(EstimateFundamentalMatrix, FindsModelWithHalfOutliers) {
  SyntheticOptions o = testing::ZoomBox();
  o.noise_sigma = 0.5;
  o.outlier_ratio = 0.3;  // per observation: ~51 % of the matches have an outlier end
  const SyntheticScene scene = GenerateSyntheticScene(o);
  const testing::Matches m = testing::PairMatches(scene, 0, 2);
  RansacOptions options;
  options.max_error = 2.0;
  const auto report = EstimateFundamentalMatrix(m.x1, m.x2, options);
  ASSERT_TRUE(report.success);
  double recall, precision;
  testing::InlierQuality(report.inlier_mask, m.outlier, &recall, &precision);
  EXPECT_GT(recall, 0.95);
  EXPECT_GT(precision, 0.95);
  // Same seed, same answer; the true F explains the reported model's inliers.
  const auto again = EstimateFundamentalMatrix(m.x1, m.x2, options);
  EXPECT_EQ(again.inlier_mask, report.inlier_mask);
  EXPECT_EQ(again.model, report.model);
  EXPECT_EQ(again.iterations, report.iterations);
}

TEST(RefineFundamentalMatrix, LowersSampsonCostAndStaysRank2) {
  SyntheticOptions o = testing::ZoomBox();
  o.noise_sigma = 1.0;
  const SyntheticScene scene = GenerateSyntheticScene(o);
  testing::Matches m = testing::PairMatches(scene, 0, 2);
  m.x1.resize(300);
  m.x2.resize(300);
  Eigen::Matrix3d F8;
  ASSERT_TRUE(Fundamental8pt(m.x1, m.x2, &F8));
  const auto cost = [&](const Eigen::Matrix3d& F) {
    double c = 0;
    for (size_t i = 0; i < m.x1.size(); ++i) c += SampsonErrorSquared(F, m.x1[i], m.x2[i]);
    return c;
  };
  const Eigen::Matrix3d F = RefineFundamentalMatrix(m.x1, m.x2, F8);
  EXPECT_LT(cost(F), cost(F8));
  EXPECT_NEAR(F.determinant(), 0.0, 1e-12);
  EXPECT_NEAR(F.norm(), 1.0, 1e-12);
  // A least-squares fit absorbs part of the noise, so the optimum's Sampson cost is below
  // that of the ground-truth F on the same noisy data.
  const Eigen::Matrix3d F_true =
      FundamentalFromProjections(scene.ProjectionMatrix(0), scene.ProjectionMatrix(2));
  EXPECT_LT(cost(F), cost(F_true));
}

}  // namespace
}  // namespace varsfm
