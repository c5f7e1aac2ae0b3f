#include "varsfm/mesh/nearest_points.h"

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "varsfm/util/error.h"
#include "varsfm/util/random.h"

namespace varsfm {
namespace {

// The definition, by brute force.
double BruteForceSpacing(const std::vector<Eigen::Vector3d>& points) {
  double sum = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    for (size_t j = 0; j < points.size(); ++j)
      if (j != i) best = std::min(best, (points[j] - points[i]).squaredNorm());
    sum += std::sqrt(best);
  }
  return sum / static_cast<double>(points.size());
}

TEST(AverageNearestSpacing, IsTheMeanOverEveryPointWithItsOutliersAndDuplicates) {
  // A noisy plane, a few far points (a dense cloud's long tail of isolated depths) and a
  // duplicate: the mean over all of them, not over a sample.
  Rng rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0), noise(-0.002, 0.002);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 3000; ++i) points.emplace_back(unit(rng), unit(rng), noise(rng));
  for (int i = 0; i < 20; ++i) points.emplace_back(3 * unit(rng), 3 * unit(rng), 1 + unit(rng));
  points.push_back(points[17]);
  EXPECT_NEAR(AverageNearestSpacing(points), BruteForceSpacing(points), 1e-12);
}

TEST(AverageNearestSpacing, OfARegularGridIsItsStep) {
  std::vector<Eigen::Vector3d> points;
  for (int x = 0; x < 40; ++x)
    for (int y = 0; y < 30; ++y) points.emplace_back(0.25 * x, 0.25 * y, 7.0);
  EXPECT_NEAR(AverageNearestSpacing(points), 0.25, 1e-12);
}

TEST(AverageNearestSpacing, AlmostTheSameCloudGivesAlmostTheSameSpacing) {
  // Dropping one point in a thousand of a cloud with a heavy tail of isolated points changes
  // the spacing by about that much (a sample's mean moved by several per cent).
  Rng rng(9);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Eigen::Vector3d> points, fewer;
  for (int i = 0; i < 20000; ++i) {
    const double spread = unit(rng) < 0.02 ? 0.2 : 0.002;  // 2 % isolated points
    points.emplace_back(unit(rng), unit(rng), spread * unit(rng));
    if (i % 1000 != 999) fewer.push_back(points.back());
  }
  const double all = AverageNearestSpacing(points), some = AverageNearestSpacing(fewer);
  EXPECT_NEAR(some / all, 1.0, 0.005);
}

TEST(AverageNearestSpacing, NeedsTwoPoints) {
  EXPECT_THROW(AverageNearestSpacing({Eigen::Vector3d::Zero()}), Error);
}

}  // namespace
}  // namespace varsfm
