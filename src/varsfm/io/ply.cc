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

// The viewpoint element after the vertices (elements between are read and dropped); checks that
// every visibility index names one.
void ReadViewpoints(ply::ValueReader& reader, const ply::Header& header, const fs::path& file,
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
  for (size_t i = 0; i < cloud->visibility.size(); ++i)
    for (uint32_t v : cloud->visibility[i])
      if (v >= cloud->viewpoints.size())
        Fail("{}: vertex {} is seen from viewpoint {} of {}", file.string(), i, v,
             cloud->viewpoints.size());
}

}  // namespace

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
    const char* type = options.double_precision ? "double" : "float";
    out << "ply\nformat binary_little_endian 1.0\ncomment written by varsfm\n"
        << fmt::format("element vertex {}\n", n);
    for (const char* axis : {"x", "y", "z"}) out << fmt::format("property {} {}\n", type, axis);
    if (cloud.HasNormals())
      for (const char* axis : {"nx", "ny", "nz"})
        out << fmt::format("property {} {}\n", type, axis);
    if (cloud.HasColors()) out << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    if (cloud.HasVisibility()) {
      out << "property list uchar uint visibility\n"
          << fmt::format("element viewpoint {}\n", cloud.viewpoints.size())
          << "property double x\nproperty double y\nproperty double z\n";
    }
    out << "end_header\n";
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

PointCloud ReadPly(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) Fail("{}: cannot open", file.string());
  const ply::Header header = ply::ReadHeader(in, file);
  if (header.elements.empty()) Fail("{}: no vertex element", file.string());
  // Elements before the vertices would have to be skipped; writers put vertices first.
  const ply::Element& vertex = header.elements.front();
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
  auto has = [&](std::initializer_list<const char*> names) {
    return std::all_of(names.begin(), names.end(), [&](const char* n) { return index.count(n); });
  };
  if (!has({"x", "y", "z"})) Fail("{}: vertices lack x y z", file.string());
  const bool normals = has({"nx", "ny", "nz"}), colors = has({"red", "green", "blue"});
  const bool visibility = has({"visibility"});

  PointCloud cloud;
  ply::ValueReader reader(in, header.binary);
  std::vector<double> values;
  std::vector<std::vector<double>> lists;  // the visibility list, if any
  for (size_t v = 0; v < vertex.count; ++v) {
    if (!ply::ReadRecord(reader, vertex, &values, &lists)) {
      if (header.binary) Fail("{}: truncated at vertex {}", file.string(), v);
      Fail("{}: bad or truncated ascii vertex {}", file.string(), v);
    }
    auto vec = [&](const char* a, const char* b, const char* c) {
      return Eigen::Vector3d(values[index[a]], values[index[b]], values[index[c]]);
    };
    // Refused here, where the file is known, rather than by every stage: a NaN or an infinity
    // crashes the Poisson octree and sends grids and the Delaunay surface's ray walks astray.
    cloud.points.push_back(vec("x", "y", "z"));
    if (!cloud.points.back().allFinite())
      Fail("{} has non-finite coordinates (vertex {})", file.string(), v);
    if (normals) {
      cloud.normals.push_back(vec("nx", "ny", "nz"));
      if (!cloud.normals.back().allFinite())
        Fail("{} has a non-finite normal (vertex {})", file.string(), v);
    }
    if (colors)
      cloud.colors.emplace_back(ply::ColorByte(values[index["red"]]),
                                ply::ColorByte(values[index["green"]]),
                                ply::ColorByte(values[index["blue"]]));
    if (visibility) {
      std::vector<uint32_t>& views = cloud.visibility.emplace_back();
      for (double v : lists[index["visibility"]]) {
        if (!(v >= 0 && v < 4294967296.0))
          Fail("{}: bad visibility index {} at vertex {}", file.string(), v,
               cloud.points.size() - 1);
        views.push_back(static_cast<uint32_t>(v));
      }
    }
  }
  if (visibility) ReadViewpoints(reader, header, file, &cloud);
  return cloud;
}

}  // namespace varsfm
