#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "estimators/test_scenes.h"
#include "varsfm/estimators/neighbourhood_graph.h"
#include "varsfm/estimators/ransac.h"
#include "varsfm/estimators/two_view_estimators.h"

namespace varsfm {
namespace {

TEST(CorrespondenceNeighbourhood, HasExactlyThePairsWithinItsRadius) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 640);
  std::normal_distribution<double> jitter(0, 4);
  std::vector<Eigen::Vector2d> x1, x2;
  for (int i = 0; i < 600; ++i) {
    x1.emplace_back(u(rng), u(rng) * 0.75);
    // Most move alike (a shift), a sixth land anywhere.
    x2.push_back(i % 6 == 0 ? Eigen::Vector2d(u(rng), u(rng) * 0.75)
                            : Eigen::Vector2d(x1.back() + Eigen::Vector2d(30 + jitter(rng), 5)));
  }
  const double mean_neighbours = 6;
  const NeighbourhoodGraph graph = CorrespondenceNeighbourhood(x1, x2, mean_neighbours);
  // The radius of the header's formula, from x1's bounding box.
  Eigen::Vector2d lo = x1[0], hi = x1[0];
  for (const auto& x : x1) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const double radius2 = mean_neighbours * (hi - lo).prod() / (M_PI * x1.size());
  std::vector<std::pair<int, int>> expected;
  for (int i = 0; i < static_cast<int>(x1.size()); ++i)
    for (int j = i + 1; j < static_cast<int>(x1.size()); ++j)
      if ((x1[i] - x1[j]).squaredNorm() + (x2[i] - x2[j]).squaredNorm() <= radius2)
        expected.emplace_back(i, j);
  EXPECT_EQ(graph.edges, expected);
  ASSERT_GT(expected.size(), 300u);  // the test means something
  // The matches that land anywhere have far fewer neighbours than those that move alike.
  std::vector<int> degree(x1.size(), 0);
  for (const auto& [i, j] : graph.edges) ++degree[i], ++degree[j];
  double wild = 0, alike = 0;
  for (size_t i = 0; i < x1.size(); ++i) (i % 6 == 0 ? wild : alike) += degree[i];
  EXPECT_LT(wild / 100, 0.2 * alike / 500);
}

// Correspondences on one row of image 1 (x1's bounding box has no area) and some sharing a
// point: the pairs are still exactly those within the radius.
TEST(CorrespondenceNeighbourhood, ExactOnALineAndWithCoincidentPoints) {
  std::vector<Eigen::Vector2d> x1, x2;
  for (int i = 0; i < 200; ++i) {
    x1.emplace_back(i % 50 == 0 ? 10.0 : 3.0 * i, 120);
    x2.emplace_back(i % 50 == 0 ? 10.0 : 3.0 * i + (i % 7), 80);
  }
  const NeighbourhoodGraph graph = CorrespondenceNeighbourhood(x1, x2, 6);
  // The radius of the header's formula: the area is clamped to 1, the radius to 1 pixel.
  std::vector<std::pair<int, int>> expected;
  for (int i = 0; i < 200; ++i)
    for (int j = i + 1; j < 200; ++j)
      if ((x1[i] - x1[j]).squaredNorm() + (x2[i] - x2[j]).squaredNorm() <= 1.0)
        expected.emplace_back(i, j);
  EXPECT_EQ(graph.edges, expected);
  EXPECT_EQ(expected.size(), 6u);  // the four coincident ones
}

TEST(CorrespondenceNeighbourhood, EmptyForFewerThanTwoPoints) {
  EXPECT_TRUE(CorrespondenceNeighbourhood({}, {}, 6).edges.empty());
  EXPECT_TRUE(CorrespondenceNeighbourhood({{1, 1}}, {{2, 2}}, 6).edges.empty());
}

TEST(GraphCutInliers, IsTheLeastEnergyLabelling) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-3, 3);
  for (int trial = 0; trial < 50; ++trial) {
    testing::ShiftEstimator estimator;
    for (int i = 0; i < 9; ++i) estimator.x.push_back(u(rng));
    NeighbourhoodGraph graph;
    for (int i = 0; i < 9; ++i)
      for (int j = i + 1; j < 9; ++j)
        if ((i * 7 + j * 3 + trial) % 4 == 0) graph.edges.emplace_back(i, j);
    const double t2 = 1.0, lambda = (trial % 5) / 5.0 + 0.1;
    std::vector<int> inliers;
    ransac_internal::GraphCutInliers(estimator, 0.0, t2, graph, lambda, &inliers);
    // The energy of the header, every labelling enumerated.
    const auto energy = [&](int labels) {  // bit i set: datum i is an inlier
      double E = 0;
      std::vector<double> e(9);
      for (int i = 0; i < 9; ++i) {
        e[i] = estimator.SquaredResidual(0.0, i) / (2.25 * t2);
        const bool in = labels >> i & 1;
        if (e[i] > 1)
          E += in ? (1 - lambda) * e[i] : 0;
        else
          E += in ? 0 : (1 - lambda) * (1 - e[i]);
        e[i] = std::min(e[i], 1.0);
      }
      for (const auto& [p, q] : graph.edges) {
        const bool a = labels >> p & 1, b = labels >> q & 1;
        E += a != b ? lambda : (!a ? lambda * 0.5 * (e[p] + e[q]) : 0);
      }
      return E;
    };
    double best = 1e300;
    for (int labels = 0; labels < 512; ++labels) best = std::min(best, energy(labels));
    int found = 0;
    for (const int i : inliers) found |= 1 << i;
    EXPECT_NEAR(energy(found), best, 1e-9) << trial;
  }
}

TEST(GraphCutRansac, FindsTheFundamentalMatrixAmongHalfOutliers) {
  SyntheticOptions o = testing::ZoomBox();
  o.noise_sigma = 0.5;
  o.outlier_ratio = 0.3;
  const SyntheticScene scene = GenerateSyntheticScene(o);
  const testing::Matches m = testing::PairMatches(scene, 0, 2);
  RansacOptions options;
  options.max_error = 2.0;
  const NeighbourhoodGraph graph = CorrespondenceNeighbourhood(m.x1, m.x2, 6);
  for (const double lambda : {0.2, 0.975}) {
    options.spatial_coherence = lambda;
    const auto report = EstimateFundamentalMatrix(m.x1, m.x2, options, &graph);
    ASSERT_TRUE(report.success);
    double recall, precision;
    testing::InlierQuality(report.inlier_mask, m.outlier, &recall, &precision);
    EXPECT_GT(recall, 0.95) << lambda;
    EXPECT_GT(precision, 0.95) << lambda;
    const auto again = EstimateFundamentalMatrix(m.x1, m.x2, options, &graph);
    EXPECT_EQ(again.model, report.model);
    EXPECT_EQ(again.inlier_mask, report.inlier_mask);
  }
}

}  // namespace
}  // namespace varsfm
