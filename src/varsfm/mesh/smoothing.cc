#include "varsfm/mesh/smoothing.h"

#include <algorithm>
#include <vector>

namespace varsfm {

void TaubinSmooth(int iterations, TriangleMesh* mesh, double lambda, double mu) {
  const size_t n = mesh->vertices.size();
  // Each vertex's edge neighbours, sorted and unique (so sums run in a fixed order).
  std::vector<std::vector<int>> neighbours(n);
  for (const Eigen::Vector3i& f : mesh->faces)
    for (int k = 0; k < 3; ++k) {
      neighbours[f[k]].push_back(f[(k + 1) % 3]);
      neighbours[f[k]].push_back(f[(k + 2) % 3]);
    }
  for (std::vector<int>& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  std::vector<Eigen::Vector3d> moved(n);
  const auto step = [&](double factor) {
    for (size_t i = 0; i < n; ++i) {
      moved[i] = mesh->vertices[i];
      if (neighbours[i].empty()) continue;
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (int j : neighbours[i]) mean += mesh->vertices[j];
      mean /= static_cast<double>(neighbours[i].size());
      moved[i] += factor * (mean - mesh->vertices[i]);
    }
    mesh->vertices.swap(moved);
  };
  for (int i = 0; i < iterations; ++i) {
    step(lambda);
    step(mu);
  }
}

}  // namespace varsfm
