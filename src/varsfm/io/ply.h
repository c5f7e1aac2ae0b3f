#pragma once
// Coloured point clouds as PLY (binary little-endian): vertex x y z (float or double),
// optional nx ny nz, red green blue (uchar) — the layout MeshLab, Open3D and CloudCompare read —
// and optional visibility: a vertex list property `visibility` (uint indices) into a second
// element `viewpoint` (double x y z, the camera centres), which viewers skip.
#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "varsfm/io/ply_format.h"
#include "varsfm/scene/point_cloud.h"
#include "varsfm/scene/reconstruction.h"

namespace varsfm {

struct PlyWriteOptions {
  // float halves the file and is what viewers expect; double keeps georeferenced coordinates
  // (large offsets) exact.
  bool double_precision = false;
};

// The header WritePly writes for `points` vertices (x y z, then nx ny nz and red green blue where
// asked), with the visibility list and `viewpoints` viewpoint records when `visibility`.
std::string PointCloudPlyHeader(size_t points, bool normals, bool colors, bool visibility,
                                size_t viewpoints, const PlyWriteOptions& options = {});

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

// One vertex of a PLY point cloud; the fields the file lacks stay empty or zero.
struct PlyPoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  Eigen::Matrix<uint8_t, 3, 1> color = Eigen::Matrix<uint8_t, 3, 1>::Zero();
  std::vector<uint32_t> visibility;  // indices into the viewpoints
};

// ReadPly's reading one vertex at a time, for a cloud that need not be held whole (the mesh
// stage merges a cloud larger than the memory as it reads it). Throws varsfm::Error as ReadPly.
class PlyPointReader {
 public:
  explicit PlyPointReader(const std::filesystem::path& file);  // reads the header
  PlyPointReader(const PlyPointReader&) = delete;
  PlyPointReader& operator=(const PlyPointReader&) = delete;

  size_t size() const { return header_.elements.front().count; }
  bool has_normals() const { return normals_; }
  bool has_colors() const { return colors_; }
  bool has_visibility() const { return visibility_; }

  // The next vertex (at most size() of them).
  void Next(PlyPoint* point);
  // Once every vertex is read: the viewpoint element (none without visibility), every visibility
  // index read checked against it.
  std::vector<Eigen::Vector3d> ReadViewpoints();

 private:
  std::filesystem::path file_;
  std::ifstream in_;
  ply::Header header_;
  std::optional<ply::ValueReader> reader_;
  // Positions in a vertex record, looked up once: by name per value, they were most of a read.
  std::array<size_t, 3> position_{}, normal_{}, color_{};
  size_t visibility_list_ = 0;
  bool normals_ = false, colors_ = false, visibility_ = false;
  size_t next_ = 0;
  size_t viewpoints_ = 0;  // records of the viewpoint element the header declares
  // The first vertex seen from a viewpoint the file does not have, and that index.
  std::optional<std::pair<size_t, size_t>> bad_index_;
  std::vector<double> values_;
  std::vector<std::vector<double>> lists_;
};

}  // namespace varsfm
