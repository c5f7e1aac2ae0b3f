#include "varsfm/io/ply.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "varsfm/util/error.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;

template <typename T>
void Put(std::ostream& out, T value) {
  if constexpr (std::endian::native == std::endian::big) {
    auto* bytes = reinterpret_cast<char*>(&value);
    std::reverse(bytes, bytes + sizeof(T));
  }
  out.write(reinterpret_cast<const char*>(&value), sizeof(T));
}

// A scalar PLY property: its name, its type's size and how to read it as a double.
struct Property {
  std::string name;
  std::string type;
  size_t size = 0;
};

size_t TypeSize(const std::string& type) {
  static const std::map<std::string, size_t> sizes = {
      {"char", 1},  {"uchar", 1},   {"int8", 1},   {"uint8", 1},  {"short", 2}, {"ushort", 2},
      {"int16", 2}, {"uint16", 2},  {"int", 4},    {"uint", 4},   {"int32", 4}, {"uint32", 4},
      {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
  const auto it = sizes.find(type);
  return it == sizes.end() ? 0 : it->second;
}

double Decode(const char* bytes, const std::string& type) {
  auto as = [&]<typename T>(T) {
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    if constexpr (std::endian::native == std::endian::big) {
      auto* b = reinterpret_cast<char*>(&value);
      std::reverse(b, b + sizeof(T));
    }
    return static_cast<double>(value);
  };
  if (type == "char" || type == "int8") return as(int8_t{});
  if (type == "uchar" || type == "uint8") return as(uint8_t{});
  if (type == "short" || type == "int16") return as(int16_t{});
  if (type == "ushort" || type == "uint16") return as(uint16_t{});
  if (type == "int" || type == "int32") return as(int32_t{});
  if (type == "uint" || type == "uint32") return as(uint32_t{});
  if (type == "float" || type == "float32") return as(float{});
  return as(double{});
}

struct Header {
  bool binary = false;
  size_t num_vertices = 0;
  std::vector<Property> vertex_properties;
};

Header ReadHeader(std::istream& in, const fs::path& file) {
  std::string line;
  if (!std::getline(in, line) || line.rfind("ply", 0) != 0)
    Fail("{}: not a PLY file", file.string());
  Header header;
  bool in_vertex = false, seen_vertex = false;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream s(line);
    std::string keyword;
    s >> keyword;
    if (keyword == "end_header") {
      if (!seen_vertex) Fail("{}: no vertex element", file.string());
      return header;
    }
    if (keyword == "format") {
      std::string format;
      s >> format;
      if (format == "binary_little_endian")
        header.binary = true;
      else if (format != "ascii")
        Fail("{}: PLY format {} is not supported", file.string(), format);
    } else if (keyword == "element") {
      std::string name;
      size_t count = 0;
      s >> name >> count;
      // Elements before the vertices would have to be skipped; writers put vertices first.
      if (!seen_vertex && name != "vertex")
        Fail("{}: element {} before the vertices is not supported", file.string(), name);
      in_vertex = name == "vertex";
      if (in_vertex) {
        header.num_vertices = count;
        seen_vertex = true;
      }
    } else if (keyword == "property" && in_vertex) {
      Property p;
      s >> p.type >> p.name;
      p.size = TypeSize(p.type);
      if (p.size == 0) Fail("{}: vertex property type {} is not supported", file.string(), p.type);
      header.vertex_properties.push_back(p);
    }
  }
  Fail("{}: PLY header without end_header", file.string());
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
  const fs::path tmp =
      file.parent_path() / fmt::format(".{}.tmp-{}", file.filename().string(), ::getpid());
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) Fail("{}: cannot open for writing", file.string());
    const char* type = options.double_precision ? "double" : "float";
    out << "ply\nformat binary_little_endian 1.0\ncomment written by varsfm\n"
        << fmt::format("element vertex {}\n", n);
    for (const char* axis : {"x", "y", "z"}) out << fmt::format("property {} {}\n", type, axis);
    if (cloud.HasNormals())
      for (const char* axis : {"nx", "ny", "nz"})
        out << fmt::format("property {} {}\n", type, axis);
    if (cloud.HasColors()) out << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    out << "end_header\n";
    auto put_vector = [&](const Eigen::Vector3d& v) {
      for (int k = 0; k < 3; ++k) {
        if (options.double_precision)
          Put<double>(out, v[k]);
        else
          Put<float>(out, static_cast<float>(v[k]));
      }
    };
    for (size_t i = 0; i < n; ++i) {
      put_vector(cloud.points[i]);
      if (cloud.HasNormals()) put_vector(cloud.normals[i]);
      if (cloud.HasColors())
        for (int k = 0; k < 3; ++k) Put<uint8_t>(out, cloud.colors[i][k]);
    }
    out.close();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      Fail("{}: write failed (disk full?)", file.string());
    }
  }
  std::error_code ec;
  fs::rename(tmp, file, ec);
  if (ec) {
    fs::remove(tmp, ec);
    Fail("{}: cannot write: {}", file.string(), ec.message());
  }
}

void WritePly(const Reconstruction& reconstruction, const fs::path& file,
              const PlyWriteOptions& options) {
  WritePly(file, SparsePointCloud(reconstruction), options);
}

PointCloud ReadPly(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) Fail("{}: cannot open", file.string());
  const Header header = ReadHeader(in, file);
  std::map<std::string, size_t> index;  // property name -> position in a vertex record
  for (size_t i = 0; i < header.vertex_properties.size(); ++i)
    index[header.vertex_properties[i].name] = i;
  auto has = [&](std::initializer_list<const char*> names) {
    return std::all_of(names.begin(), names.end(), [&](const char* n) { return index.count(n); });
  };
  if (!has({"x", "y", "z"})) Fail("{}: vertices lack x y z", file.string());
  const bool normals = has({"nx", "ny", "nz"}), colors = has({"red", "green", "blue"});

  PointCloud cloud;
  std::vector<double> values(header.vertex_properties.size());
  std::string record;
  for (size_t v = 0; v < header.num_vertices; ++v) {
    if (header.binary) {
      for (size_t i = 0; i < values.size(); ++i) {
        const Property& p = header.vertex_properties[i];
        record.resize(p.size);
        if (!in.read(record.data(), static_cast<std::streamsize>(p.size)))
          Fail("{}: truncated at vertex {}", file.string(), v);
        values[i] = Decode(record.data(), p.type);
      }
    } else {
      for (double& value : values)
        if (!(in >> value)) Fail("{}: bad or truncated ascii vertex {}", file.string(), v);
    }
    auto vec = [&](const char* a, const char* b, const char* c) {
      return Eigen::Vector3d(values[index[a]], values[index[b]], values[index[c]]);
    };
    cloud.points.push_back(vec("x", "y", "z"));
    if (normals) cloud.normals.push_back(vec("nx", "ny", "nz"));
    if (colors) cloud.colors.push_back(vec("red", "green", "blue").cast<uint8_t>());
  }
  return cloud;
}

}  // namespace varsfm
