#pragma once
// An indexed triangle mesh with per-vertex colours: the mesh stage's result and the texture
// stage's input. The data type only; io/mesh_ply.h reads and writes it.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace varsfm {

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Matrix<uint8_t, 3, 1>> colors;  // empty, or one per vertex
  std::vector<Eigen::Vector3i> faces;                // counter-clockwise seen from outside
};

}  // namespace varsfm
