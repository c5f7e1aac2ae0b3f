#pragma once
// An indexed triangle mesh with per-vertex colours: the mesh stage's result and the texture
// stage's input. The data type only; io/mesh_ply.h reads and writes it.
#include <algorithm>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace varsfm {

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Matrix<uint8_t, 3, 1>> colors;  // empty, or one per vertex
  std::vector<Eigen::Vector3i> faces;                // counter-clockwise seen from outside
};

// The key of the undirected edge between vertices a and b, the same in either order: the
// smaller index in the high 32 bits. For the maps and sorts that find the faces sharing an edge.
inline uint64_t UndirectedEdgeKey(uint32_t a, uint32_t b) {
  return (static_cast<uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
}

}  // namespace varsfm
