#include "varsfm/io/ply.h"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <string>

#include "varsfm/io/ply_format.h"
#include "varsfm/util/atomic_file.h"
#include "varsfm/util/error.h"
#include "varsfm/util/little_endian.h"

namespace varsfm {

namespace fs = std::filesystem;

namespace {

// The viewpoint element after the vertices (elements between are read and dropped).
void ReadViewpointElement(ply::ValueReader& reader, const ply::Header& header, const fs::path& file,
                          PointCloud* cloud) {
  std::vector<double> values;
  std::vector<std::vector<double>> lists;
  for (size_t e = 1; e < header.elements.size(); ++e) {
    const ply::Element& element = header.elements[e];
    ply::RequireKnownTypes(element, file);
    const bool viewpoint = element.name == "viewpoint";
    std::map<std::string, size_t> index;
    for (size_t i = 0; i < element.properties.size(); ++i) index[element.properties[i].name] = i;
    if (viewpoint && (!index.count("x") || !index.count("y") || !index.count("z")))
      Fail("{}: viewpoints lack x y z", file.string());
    for (size_t r = 0; r < element.count; ++r) {
      if (!ply::ReadRecord(reader, element, &values, &lists))
        Fail("{}: truncated at {} {}", file.string(), element.name, r);
      if (!viewpoint) continue;
      const Eigen::Vector3d& centre = cloud->viewpoints.emplace_back(
          values[index["x"]], values[index["y"]], values[index["z"]]);
      // A ray from a non-finite camera centre would walk the tetrahedra with NaN parameters.
      if (!centre.allFinite())
        Fail("{}: viewpoint {} has non-finite coordinates", file.string(), r);
    }
    if (viewpoint) break;
  }
}

}  // namespace

std::string PointCloudPlyHeader(size_t points, bool normals, bool colors, bool visibility,
                                size_t viewpoints, const PlyWriteOptions& options) {
  const char* type = options.double_precision ? "double" : "float";
  std::string header = fmt::format(
      "ply\nformat binary_little_endian 1.0\ncomment written by varsfm\nelement vertex {}\n",
      points);
  for (const char* axis : {"x", "y", "z"}) header += fmt::format("property {} {}\n", type, axis);
  if (normals)
    for (const char* axis : {"nx", "ny", "nz"})
      header += fmt::format("property {} {}\n", type, axis);
  if (colors) header += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (visibility)
    header += fmt::format(
        "property list uchar uint visibility\nelement viewpoint {}\nproperty double x\n"
        "property double y\nproperty double z\n",
        viewpoints);
  return header + "end_header\n";
}

PointCloud SparsePointCloud(const Reconstruction& reconstruction) {
  PointCloud cloud;
  for (const auto& [id, point] : reconstruction.points3D()) {
    cloud.points.push_back(point.xyz);
    cloud.colors.push_back(point.color);
  }
  return cloud;
}

void WritePly(const fs::path& file, const PointCloud& cloud, const PlyWriteOptions& options) {
  const size_t n = cloud.points.size();
  if (cloud.HasNormals() && cloud.normals.size() != n)
    Fail("{}: {} normals for {} points", file.string(), cloud.normals.size(), n);
  if (cloud.HasColors() && cloud.colors.size() != n)
    Fail("{}: {} colours for {} points", file.string(), cloud.colors.size(), n);
  if (cloud.HasVisibility() && cloud.visibility.size() != n)
    Fail("{}: {} visibility lists for {} points", file.string(), cloud.visibility.size(), n);
  for (const std::vector<uint32_t>& views : cloud.visibility) {
    if (views.size() > 255)
      Fail("{}: a point seen by {} views (at most 255)", file.string(), views.size());
    for (uint32_t v : views)
      if (v >= cloud.viewpoints.size())
        Fail("{}: visibility index {} with {} viewpoints", file.string(), v,
             cloud.viewpoints.size());
  }
  WriteFileAtomically(file, [&](std::ostream& out) {
    out << PointCloudPlyHeader(n, cloud.HasNormals(), cloud.HasColors(), cloud.HasVisibility(),
                               cloud.viewpoints.size(), options);
    auto put_vector = [&](const Eigen::Vector3d& v) {
      for (int k = 0; k < 3; ++k) {
        if (options.double_precision)
          PutLittleEndian<double>(out, v[k]);
        else
          PutLittleEndian<float>(out, static_cast<float>(v[k]));
      }
    };
    for (size_t i = 0; i < n; ++i) {
      put_vector(cloud.points[i]);
      if (cloud.HasNormals()) put_vector(cloud.normals[i]);
      if (cloud.HasColors())
        for (int k = 0; k < 3; ++k) PutLittleEndian<uint8_t>(out, cloud.colors[i][k]);
      if (cloud.HasVisibility()) {
        PutLittleEndian<uint8_t>(out, static_cast<uint8_t>(cloud.visibility[i].size()));
        for (uint32_t v : cloud.visibility[i]) PutLittleEndian<uint32_t>(out, v);
      }
    }
    if (cloud.HasVisibility())
      for (const Eigen::Vector3d& c : cloud.viewpoints)
        for (int k = 0; k < 3; ++k) PutLittleEndian<double>(out, c[k]);
  });
}

void WritePly(const Reconstruction& reconstruction, const fs::path& file,
              const PlyWriteOptions& options) {
  WritePly(file, SparsePointCloud(reconstruction), options);
}

PlyPointReader::PlyPointReader(const fs::path& file) : file_(file), in_(file, std::ios::binary) {
  if (!in_) Fail("{}: cannot open", file.string());
  header_ = ply::ReadHeader(in_, file);
  if (header_.elements.empty()) Fail("{}: no vertex element", file.string());
  // Elements before the vertices would have to be skipped; writers put vertices first.
  const ply::Element& vertex = header_.elements.front();
  if (vertex.name != "vertex")
    Fail("{}: element {} before the vertices is not supported", file.string(), vertex.name);
  ply::RequireKnownTypes(vertex, file);
  std::map<std::string, size_t> index;  // property name -> position in a vertex record
  for (size_t i = 0; i < vertex.properties.size(); ++i) {
    // A point cloud's only vertex list is its visibility; another is taken for a malformed file.
    if (vertex.properties[i].IsList() && vertex.properties[i].name != "visibility")
      Fail("{}: vertex property type list is not supported", file.string());
    index[vertex.properties[i].name] = i;
  }
  // Whether every name is a property, and then their positions.
  auto find = [&](std::array<const char*, 3> names, std::array<size_t, 3>* positions) {
    for (int k = 0; k < 3; ++k) {
      const auto it = index.find(names[k]);
      if (it == index.end()) return false;
      (*positions)[k] = it->second;
    }
    return true;
  };
  if (!find({"x", "y", "z"}, &position_)) Fail("{}: vertices lack x y z", file.string());
  normals_ = find({"nx", "ny", "nz"}, &normal_);
  colors_ = find({"red", "green", "blue"}, &color_);
  visibility_ = index.count("visibility") > 0;
  if (visibility_) visibility_list_ = index.at("visibility");
  for (const ply::Element& element : header_.elements)
    if (element.name == "viewpoint") {
      viewpoints_ = element.count;
      break;
    }
  reader_.emplace(in_, header_.binary);
}

void PlyPointReader::Next(PlyPoint* point) {
  const size_t v = next_++;
  if (v >= size()) Fail("{}: read past its {} vertices", file_.string(), size());
  if (!ply::ReadRecord(*reader_, header_.elements.front(), &values_, &lists_)) {
    if (header_.binary) Fail("{}: truncated at vertex {}", file_.string(), v);
    Fail("{}: bad or truncated ascii vertex {}", file_.string(), v);
  }
  auto vec = [&](const std::array<size_t, 3>& at) {
    return Eigen::Vector3d(values_[at[0]], values_[at[1]], values_[at[2]]);
  };
  // Refused here, where the file is known, rather than by every stage: a NaN or an infinity
  // crashes the Poisson octree and sends grids and the Delaunay surface's ray walks astray.
  point->position = vec(position_);
  if (!point->position.allFinite())
    Fail("{} has non-finite coordinates (vertex {})", file_.string(), v);
  if (normals_) {
    point->normal = vec(normal_);
    if (!point->normal.allFinite())
      Fail("{} has a non-finite normal (vertex {})", file_.string(), v);
  }
  if (colors_)
    point->color = {ply::ColorByte(values_[color_[0]]), ply::ColorByte(values_[color_[1]]),
                    ply::ColorByte(values_[color_[2]])};
  point->visibility.clear();
  if (!visibility_) return;
  for (double i : lists_[visibility_list_]) {
    if (!(i >= 0 && i < 4294967296.0))
      Fail("{}: bad visibility index {} at vertex {}", file_.string(), i, v);
    point->visibility.push_back(static_cast<uint32_t>(i));
    if (static_cast<size_t>(i) >= viewpoints_ && !bad_index_)
      bad_index_.emplace(v, static_cast<size_t>(i));
  }
}

std::vector<Eigen::Vector3d> PlyPointReader::ReadViewpoints() {
  if (!visibility_) return {};
  if (next_ != size())
    Fail("{}: viewpoints read before the last of its {} vertices", file_.string(), size());
  PointCloud cloud;
  ReadViewpointElement(*reader_, header_, file_, &cloud);
  if (bad_index_)
    Fail("{}: vertex {} is seen from viewpoint {} of {}", file_.string(), bad_index_->first,
         bad_index_->second, cloud.viewpoints.size());
  return std::move(cloud.viewpoints);
}

PointCloud ReadPly(const fs::path& file) {
  PlyPointReader reader(file);
  PointCloud cloud;
  PlyPoint point;
  for (size_t v = 0; v < reader.size(); ++v) {
    reader.Next(&point);
    cloud.points.push_back(point.position);
    if (reader.has_normals()) cloud.normals.push_back(point.normal);
    if (reader.has_colors()) cloud.colors.push_back(point.color);
    if (reader.has_visibility()) cloud.visibility.push_back(point.visibility);
  }
  cloud.viewpoints = reader.ReadViewpoints();
  return cloud;
}

}  // namespace varsfm
