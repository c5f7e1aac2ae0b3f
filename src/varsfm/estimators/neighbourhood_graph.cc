#include "varsfm/estimators/neighbourhood_graph.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <unordered_map>

namespace varsfm {
namespace {

using Cell = std::array<int64_t, 4>;

// 16 bits per coordinate: cells are at least a pixel, images far below 65536 of them.
uint64_t CellKey(const Cell& c) {
  uint64_t key = 0;
  for (int64_t v : c) key = (key << 16) | static_cast<uint64_t>(v & 0xffff);
  return key;
}

}  // namespace

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

  const auto cell_of = [&](size_t i) {
    return Cell{static_cast<int64_t>(std::floor(x1[i].x() / radius)),
                static_cast<int64_t>(std::floor(x1[i].y() / radius)),
                static_cast<int64_t>(std::floor(x2[i].x() / radius)),
                static_cast<int64_t>(std::floor(x2[i].y() / radius))};
  };
  std::unordered_map<uint64_t, std::vector<int>> cells;
  for (size_t i = 0; i < n; ++i) cells[CellKey(cell_of(i))].push_back(static_cast<int>(i));

  std::vector<int> found;
  for (size_t i = 0; i < n; ++i) {
    const Cell c = cell_of(i);
    found.clear();
    for (int d = 0; d < 81; ++d) {  // the 3^4 cells around c
      Cell neighbour = c;
      for (int axis = 0, code = d; axis < 4; ++axis, code /= 3) neighbour[axis] += code % 3 - 1;
      const auto it = cells.find(CellKey(neighbour));
      if (it == cells.end()) continue;
      for (const int j : it->second) {
        if (j <= static_cast<int>(i)) continue;
        const double d2 = (x1[j] - x1[i]).squaredNorm() + (x2[j] - x2[i]).squaredNorm();
        if (d2 <= radius2) found.push_back(j);
      }
    }
    std::sort(found.begin(), found.end());
    found.erase(std::unique(found.begin(), found.end()), found.end());
    for (const int j : found) graph.edges.emplace_back(static_cast<int>(i), j);
  }
  return graph;
}

}  // namespace varsfm
