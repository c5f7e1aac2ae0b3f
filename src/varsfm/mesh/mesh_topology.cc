#include "varsfm/mesh/mesh_topology.h"

#include <algorithm>
#include <numeric>
#include <unordered_map>

namespace varsfm {

EdgeTopology ComputeEdgeTopology(const TriangleMesh& mesh) {
  std::unordered_map<uint64_t, int> uses;
  uses.reserve(mesh.faces.size() * 2);
  for (const Eigen::Vector3i& f : mesh.faces) {
    for (int k = 0; k < 3; ++k) ++uses[UndirectedEdgeKey(f[k], f[(k + 1) % 3])];
  }
  EdgeTopology topology;
  topology.num_edges = uses.size();
  for (const auto& [edge, count] : uses) {
    if (count == 1) ++topology.boundary_edges;
    if (count > 2) ++topology.non_manifold_edges;
  }
  return topology;
}

std::vector<std::vector<int>> VertexNeighbours(const TriangleMesh& mesh) {
  std::vector<std::vector<int>> neighbours(mesh.vertices.size());
  for (const Eigen::Vector3i& f : mesh.faces)
    for (int k = 0; k < 3; ++k) {
      neighbours[f[k]].push_back(f[(k + 1) % 3]);
      neighbours[f[k]].push_back(f[(k + 2) % 3]);
    }
  for (std::vector<int>& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return neighbours;
}

void RemoveUnreferencedVertices(TriangleMesh* mesh) {
  std::vector<int> remap(mesh->vertices.size(), -1);
  for (const Eigen::Vector3i& f : mesh->faces) {
    for (int k = 0; k < 3; ++k) remap[f[k]] = 0;
  }
  int next = 0;
  for (size_t i = 0; i < remap.size(); ++i) {
    if (remap[i] < 0) continue;
    remap[i] = next;
    mesh->vertices[next] = mesh->vertices[i];
    if (!mesh->colors.empty()) mesh->colors[next] = mesh->colors[i];
    ++next;
  }
  mesh->vertices.resize(next);
  if (!mesh->colors.empty()) mesh->colors.resize(next);
  for (Eigen::Vector3i& f : mesh->faces) {
    for (int k = 0; k < 3; ++k) f[k] = remap[f[k]];
  }
}

std::vector<uint32_t> ComponentRoots(const TriangleMesh& mesh) {
  std::vector<uint32_t> parent(mesh.vertices.size());
  std::iota(parent.begin(), parent.end(), 0u);
  const auto find = [&](uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (const Eigen::Vector3i& f : mesh.faces)
    for (int k = 1; k < 3; ++k) {
      const uint32_t a = find(f[0]), b = find(f[k]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  for (uint32_t v = 0; v < parent.size(); ++v) parent[v] = find(v);
  return parent;
}

}  // namespace varsfm
