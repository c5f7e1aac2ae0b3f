#pragma once
// A coloured point cloud with optional normals: the sparse model's points, the dense stage's
// fused points and the mesh stage's input. The data type only; io/ply.h reads and writes it.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace varsfm {

struct PointCloud {
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3d> normals;              // empty, or one per point
  std::vector<Eigen::Matrix<uint8_t, 3, 1>> colors;  // empty, or one per point

  bool HasNormals() const { return !normals.empty(); }
  bool HasColors() const { return !colors.empty(); }
};

}  // namespace varsfm
