#include "varsfm/estimators/neighbourhood_graph.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace varsfm {

NeighbourhoodGraph CorrespondenceNeighbourhood(const std::vector<Eigen::Vector2d>& x1,
                                               const std::vector<Eigen::Vector2d>& x2,
                                               double mean_neighbours) {
  NeighbourhoodGraph graph;
  const size_t n = std::min(x1.size(), x2.size());
  if (n < 2 || !(mean_neighbours > 0)) return graph;
  Eigen::Vector2d lo = x1[0], hi = x1[0];
  for (size_t i = 0; i < n; ++i) lo = lo.cwiseMin(x1[i]), hi = hi.cwiseMax(x1[i]);
  const double area = std::max(1.0, (hi - lo).prod());
  const double radius = std::max(
      1.0, std::sqrt(mean_neighbours * area / (std::numbers::pi * static_cast<double>(n))));
  const double radius2 = radius * radius;

  // Pairs within the radius in the joint space are within it in image 1: a grid of cells of
  // that size over x1 (about n pi / mean_neighbours cells, the correspondences bucketed by a
  // counting sort) gives the candidates, the joint distance decides.
  const auto cells_along = [&](double extent) {
    return static_cast<size_t>(std::floor(extent / radius)) + 1;
  };
  const size_t columns = cells_along(hi.x() - lo.x()), rows = cells_along(hi.y() - lo.y());
  const auto cell_of = [&](size_t i) {
    const auto column = static_cast<size_t>(std::floor((x1[i].x() - lo.x()) / radius));
    const auto row = static_cast<size_t>(std::floor((x1[i].y() - lo.y()) / radius));
    return std::pair{std::min(column, columns - 1), std::min(row, rows - 1)};
  };
  std::vector<uint32_t> begin(columns * rows + 1, 0), members(n);
  for (size_t i = 0; i < n; ++i) {
    const auto [column, row] = cell_of(i);
    ++begin[row * columns + column + 1];
  }
  for (size_t c = 0; c < columns * rows; ++c) begin[c + 1] += begin[c];
  std::vector<uint32_t> next(begin.begin(), begin.end() - 1);
  for (size_t i = 0; i < n; ++i) {
    const auto [column, row] = cell_of(i);
    members[next[row * columns + column]++] = static_cast<uint32_t>(i);
  }

  std::vector<int> found;
  for (size_t i = 0; i < n; ++i) {
    const auto [column, row] = cell_of(i);
    found.clear();
    for (size_t r = row > 0 ? row - 1 : 0; r <= std::min(row + 1, rows - 1); ++r) {
      for (size_t c = column > 0 ? column - 1 : 0; c <= std::min(column + 1, columns - 1); ++c) {
        for (uint32_t k = begin[r * columns + c]; k < begin[r * columns + c + 1]; ++k) {
          const uint32_t j = members[k];
          if (j <= i) continue;
          const double d2 = (x1[j] - x1[i]).squaredNorm() + (x2[j] - x2[i]).squaredNorm();
          if (d2 <= radius2) found.push_back(static_cast<int>(j));
        }
      }
    }
    std::sort(found.begin(), found.end());
    for (const int j : found) graph.edges.emplace_back(static_cast<int>(i), j);
  }
  return graph;
}

}  // namespace varsfm
