#pragma once
// A coloured point cloud with optional normals and visibility: the sparse model's points, the dense stage's
// fused points and the mesh stage's input. The data type only; io/ply.h reads and writes it.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace varsfm {

struct PointCloud {
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3d> normals;              // empty, or one per point
  std::vector<Eigen::Matrix<uint8_t, 3, 1>> colors;  // empty, or one per point
  // Visibility: the camera centres the points were observed from, and per point the indices
  // (into viewpoints, ascending) of the cameras that observed it. A surface that carves free
  // space along the rays camera -> point needs it (mesh/delaunay_surface.h).
  std::vector<Eigen::Vector3d> viewpoints;
  std::vector<std::vector<uint32_t>> visibility;  // empty, or one per point

  bool HasNormals() const { return !normals.empty(); }
  bool HasColors() const { return !colors.empty(); }
  bool HasVisibility() const { return !visibility.empty(); }
};

}  // namespace varsfm
