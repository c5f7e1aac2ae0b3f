#pragma once
// Coloured point clouds as PLY (binary little-endian): vertex x y z (float or double),
// optional nx ny nz, red green blue (uchar) — the layout MeshLab, Open3D and CloudCompare read —
// and optional visibility: a vertex list property `visibility` (uint indices) into a second
// element `viewpoint` (double x y z, the camera centres), which viewers skip.
#include <filesystem>

#include "varsfm/scene/point_cloud.h"
#include "varsfm/scene/reconstruction.h"

namespace varsfm {

struct PlyWriteOptions {
  // float halves the file and is what viewers expect; double keeps georeferenced coordinates
  // (large offsets) exact.
  bool double_precision = false;
};

// The sparse model's 3D points with their colours (no normals), in point-id order.
PointCloud SparsePointCloud(const Reconstruction& reconstruction);

// Writes atomically (a temporary file beside `file`, then a rename). Throws varsfm::Error when
// normals/colours/visibility do not match the point count, a visibility index names no
// viewpoint, or the file cannot be written.
void WritePly(const std::filesystem::path& file, const PointCloud& cloud,
              const PlyWriteOptions& options = {});

// The sparse model's points (SparsePointCloud) written to `file`.
void WritePly(const Reconstruction& reconstruction, const std::filesystem::path& file,
              const PlyWriteOptions& options = {});

// Reads the vertex element of an ascii or binary_little_endian PLY: x y z required, nx ny nz
// and red green blue when present, any scalar property types; the visibility list and the
// viewpoint element when present. Throws varsfm::Error.
PointCloud ReadPly(const std::filesystem::path& file);

}  // namespace varsfm
