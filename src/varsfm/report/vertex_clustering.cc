#include "varsfm/report/vertex_clustering.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace varsfm {
namespace {

// Atlas squares (per side) within which corners of one cell are taken to be one chart.
constexpr double kUvBuckets = 1024;

struct Grid {
  std::array<double, 3> low;
  double cell;
  // 21 bits per axis: the grid never has more than 2^21 cells per side (see ClusterVertices).
  uint64_t Key(const float* p) const {
    uint64_t key = 0;
    for (int k = 0; k < 3; ++k)
      key = (key << 21) | static_cast<uint64_t>(std::floor((p[k] - low[k]) / cell));
    return key;
  }
};

size_t FacesLeft(const std::vector<ClusteredPart>& parts, const Grid& grid) {
  size_t left = 0;
  for (const ClusteredPart& part : parts) {
    for (size_t f = 0; f + 2 < part.indices.size(); f += 3) {
      const uint64_t a = grid.Key(&part.positions[3 * part.indices[f]]);
      const uint64_t b = grid.Key(&part.positions[3 * part.indices[f + 1]]);
      const uint64_t c = grid.Key(&part.positions[3 * part.indices[f + 2]]);
      left += a != b && b != c && a != c;
    }
  }
  return left;
}

ClusteredPart Cluster(const ClusteredPart& part, const Grid& grid,
                      const std::unordered_map<uint64_t, std::array<double, 4>>& cell_means) {
  const bool textured = !part.uvs.empty();
  const size_t n = part.positions.size() / 3;
  std::vector<uint64_t> cell(n);
  for (size_t v = 0; v < n; ++v) cell[v] = grid.Key(&part.positions[3 * v]);
  // New vertex of each old one: by cell and atlas square.
  std::unordered_map<uint64_t, std::unordered_map<uint64_t, uint32_t>> vertex_of;
  std::vector<uint32_t> new_index(n, std::numeric_limits<uint32_t>::max());
  std::vector<std::array<double, 3>> uv_sums;  // u, v, count per new vertex
  ClusteredPart out;
  for (size_t f = 0; f + 2 < part.indices.size(); f += 3) {
    const uint32_t* corner = &part.indices[f];
    if (cell[corner[0]] == cell[corner[1]] || cell[corner[1]] == cell[corner[2]] ||
        cell[corner[0]] == cell[corner[2]])
      continue;
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = corner[k];
      if (new_index[v] == std::numeric_limits<uint32_t>::max()) {
        uint64_t square = 0;
        if (textured)
          square = static_cast<uint64_t>(std::clamp(part.uvs[2 * v], 0.f, 1.f) * kUvBuckets) *
                       (kUvBuckets + 1) +
                   static_cast<uint64_t>(std::clamp(part.uvs[2 * v + 1], 0.f, 1.f) * kUvBuckets);
        auto [it, added] = vertex_of[cell[v]].try_emplace(square, uv_sums.size());
        if (added) {
          const std::array<double, 4>& mean = cell_means.at(cell[v]);
          for (int c = 0; c < 3; ++c) out.positions.push_back(mean[c] / mean[3]);
          uv_sums.push_back({0, 0, 0});
        }
        new_index[v] = it->second;
        if (textured)
          uv_sums[it->second] = {uv_sums[it->second][0] + part.uvs[2 * v],
                                 uv_sums[it->second][1] + part.uvs[2 * v + 1],
                                 uv_sums[it->second][2] + 1};
      }
      out.indices.push_back(new_index[v]);
    }
  }
  if (textured)
    for (const auto& [u, v, count] : uv_sums) {
      out.uvs.push_back(static_cast<float>(u / count));
      out.uvs.push_back(static_cast<float>(v / count));
    }
  return out;
}

}  // namespace

std::vector<ClusteredPart> ClusterVertices(const std::vector<ClusteredPart>& parts,
                                           size_t max_faces) {
  size_t faces = 0;
  Grid grid{{INFINITY, INFINITY, INFINITY}, 0};
  std::array<double, 3> high = {-INFINITY, -INFINITY, -INFINITY};
  for (const ClusteredPart& part : parts) {
    faces += part.indices.size() / 3;
    for (size_t i = 0; i < part.positions.size(); ++i) {
      grid.low[i % 3] = std::min<double>(grid.low[i % 3], part.positions[i]);
      high[i % 3] = std::max<double>(high[i % 3], part.positions[i]);
    }
  }
  if (faces <= max_faces || max_faces == 0) return parts;
  const double extent =
      std::max({high[0] - grid.low[0], high[1] - grid.low[1], high[2] - grid.low[2], 1e-12});
  // Triangles on a surface scale with 1 / cell^2: start from a fine grid and correct the cell
  // by the square root of the ratio, keeping the last size that leaves no more than max_faces.
  grid.cell = extent / 4096;
  double fitting = 0;
  for (int trial = 0; trial < 8; ++trial) {
    const size_t left = FacesLeft(parts, grid);
    if (left <= max_faces) {
      fitting = grid.cell;
      if (left >= 0.8 * max_faces) break;
    }
    const double next =
        grid.cell * std::sqrt(static_cast<double>(std::max<size_t>(left, 1)) / (0.9 * max_faces));
    grid.cell = fitting > 0 ? std::min(next, fitting) : next;
    if (fitting > 0 && grid.cell >= fitting) break;
  }
  grid.cell = fitting > 0 ? fitting : grid.cell;
  grid.cell = std::max(grid.cell, extent / ((1 << 21) - 2));

  std::unordered_map<uint64_t, std::array<double, 4>> cell_means;  // x, y, z sums and count
  for (const ClusteredPart& part : parts)
    for (size_t v = 0; v < part.positions.size() / 3; ++v) {
      std::array<double, 4>& mean = cell_means[grid.Key(&part.positions[3 * v])];
      for (int c = 0; c < 3; ++c) mean[c] += part.positions[3 * v + c];
      mean[3] += 1;
    }
  std::vector<ClusteredPart> out;
  for (const ClusteredPart& part : parts) out.push_back(Cluster(part, grid, cell_means));
  return out;
}

}  // namespace varsfm
