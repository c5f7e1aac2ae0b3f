#include "varsfm/mesh/smoothing.h"

#include <vector>

#include "varsfm/mesh/mesh_topology.h"

namespace varsfm {

void TaubinSmooth(int iterations, TriangleMesh* mesh, double lambda, double mu) {
  const size_t n = mesh->vertices.size();
  const std::vector<std::vector<int>> neighbours = VertexNeighbours(*mesh);
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
