#include "varsfm/mesh/triangle_mesh.h"

#include <algorithm>
#include <fstream>
#include <system_error>
#include <unordered_map>

#include "varsfm/util/error.h"

namespace varsfm {
namespace {

template <typename T>
void Put(std::ofstream& out, T value) {
  out.write(reinterpret_cast<const char*>(&value), sizeof(T));
}

}  // namespace

void WriteMeshPly(const std::filesystem::path& file, const TriangleMesh& mesh) {
  const bool has_colors = !mesh.colors.empty();
  if (has_colors && mesh.colors.size() != mesh.vertices.size()) {
    Fail("{}: {} colours for {} vertices", file.string(), mesh.colors.size(), mesh.vertices.size());
  }
  const int n = static_cast<int>(mesh.vertices.size());
  for (const Eigen::Vector3i& f : mesh.faces) {
    if (f.minCoeff() < 0 || f.maxCoeff() >= n) Fail("{}: face index out of range", file.string());
  }
  std::filesystem::path tmp = file;
  tmp += ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) Fail("{}: cannot write", file.string());
    out << "ply\nformat binary_little_endian 1.0\ncomment varsfm mesh\n"
        << "element vertex " << mesh.vertices.size() << "\n"
        << "property float x\nproperty float y\nproperty float z\n";
    if (has_colors) out << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    out << "element face " << mesh.faces.size() << "\n"
        << "property list uchar int vertex_indices\nend_header\n";
    for (size_t i = 0; i < mesh.vertices.size(); ++i) {
      for (int k = 0; k < 3; ++k) Put(out, static_cast<float>(mesh.vertices[i][k]));
      if (has_colors) {
        for (int k = 0; k < 3; ++k) Put(out, mesh.colors[i][k]);
      }
    }
    for (const Eigen::Vector3i& f : mesh.faces) {
      Put(out, static_cast<uint8_t>(3));
      for (int k = 0; k < 3; ++k) Put(out, static_cast<int32_t>(f[k]));
    }
    if (!out.flush()) Fail("{}: write failed", file.string());
  }
  std::error_code ec;
  std::filesystem::rename(tmp, file, ec);
  if (ec) Fail("{}: cannot write ({})", file.string(), ec.message());
}

EdgeTopology ComputeEdgeTopology(const TriangleMesh& mesh) {
  std::unordered_map<uint64_t, int> uses;
  uses.reserve(mesh.faces.size() * 2);
  for (const Eigen::Vector3i& f : mesh.faces) {
    for (int k = 0; k < 3; ++k) {
      const uint64_t a = static_cast<uint32_t>(std::min(f[k], f[(k + 1) % 3]));
      const uint64_t b = static_cast<uint32_t>(std::max(f[k], f[(k + 1) % 3]));
      ++uses[(a << 32) | b];
    }
  }
  EdgeTopology topology;
  topology.num_edges = uses.size();
  for (const auto& [edge, count] : uses) {
    if (count == 1) ++topology.boundary_edges;
    if (count > 2) ++topology.non_manifold_edges;
  }
  return topology;
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

}  // namespace varsfm
