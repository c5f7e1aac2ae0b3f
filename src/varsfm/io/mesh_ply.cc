#include "varsfm/io/mesh_ply.h"

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "varsfm/io/ply_format.h"
#include "varsfm/util/atomic_file.h"
#include "varsfm/util/error.h"
#include "varsfm/util/little_endian.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;

// Position of the property called `name` in `element`, -1 when it has none.
int PropertyIndex(const ply::Element& element, const std::string& name) {
  for (size_t k = 0; k < element.properties.size(); ++k)
    if (element.properties[k].name == name) return static_cast<int>(k);
  return -1;
}

// A face's vertex index, read as a double: checked before the conversion, which is undefined for
// NaN or values beyond int (the check against the vertex count comes once all are read).
int VertexIndex(double value, const fs::path& file) {
  if (!(value >= 0 && value < 2147483647.0)) Fail("{}: face index out of range", file.string());
  return static_cast<int>(value);
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
  WriteFileAtomically(file, [&](std::ostream& out) {
    out << "ply\nformat binary_little_endian 1.0\ncomment varsfm mesh\n"
        << "element vertex " << mesh.vertices.size() << "\n"
        << "property float x\nproperty float y\nproperty float z\n";
    if (has_colors) out << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    out << "element face " << mesh.faces.size() << "\n"
        << "property list uchar int vertex_indices\nend_header\n";
    for (size_t i = 0; i < mesh.vertices.size(); ++i) {
      for (int k = 0; k < 3; ++k) PutLittleEndian(out, static_cast<float>(mesh.vertices[i][k]));
      if (has_colors) {
        for (int k = 0; k < 3; ++k) PutLittleEndian(out, mesh.colors[i][k]);
      }
    }
    for (const Eigen::Vector3i& f : mesh.faces) {
      PutLittleEndian(out, static_cast<uint8_t>(3));
      for (int k = 0; k < 3; ++k) PutLittleEndian(out, static_cast<int32_t>(f[k]));
    }
  });
}

// The PLY grammar (header, types, ascii/binary records) is io/ply_format's; this only maps the
// vertex and face elements onto a TriangleMesh.
TriangleMesh ReadMeshPly(const fs::path& file) {
  if (!fs::is_regular_file(file)) Fail("{}: mesh file does not exist", file.string());
  std::ifstream in(file, std::ios::binary);
  if (!in) Fail("{}: cannot open", file.string());
  const ply::Header header = ply::ReadHeader(in, file);
  // Every element is read (the data is one stream), so every type must be known.
  for (const ply::Element& e : header.elements) ply::RequireKnownTypes(e, file);

  TriangleMesh mesh;
  ply::ValueReader reader(in, header.binary);
  std::vector<double> values;
  std::vector<std::vector<double>> lists;
  for (const ply::Element& e : header.elements) {
    const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
    const int ix = PropertyIndex(e, "x"), iy = PropertyIndex(e, "y"), iz = PropertyIndex(e, "z");
    const int ir = PropertyIndex(e, "red"), ig = PropertyIndex(e, "green"),
              ib = PropertyIndex(e, "blue");
    if (is_vertex && (ix < 0 || iy < 0 || iz < 0))
      Fail("{}: PLY vertices lack x y z", file.string());
    const bool has_colors = ir >= 0 && ig >= 0 && ib >= 0;
    for (size_t r = 0; r < e.count; ++r) {
      if (!ply::ReadRecord(reader, e, &values, &lists))
        Fail("{}: truncated or malformed PLY data", file.string());
      if (is_vertex) {
        // A non-finite vertex would reach the texture's rasteriser and the OBJ written from it
        // (`v nan ...`): refused with the file's name, for every stage that reads a mesh.
        if (!mesh.vertices.emplace_back(values[ix], values[iy], values[iz]).allFinite())
          Fail("{} has non-finite coordinates (vertex {})", file.string(), r);
        if (has_colors)
          mesh.colors.emplace_back(ply::ColorByte(values[ir]), ply::ColorByte(values[ig]),
                                   ply::ColorByte(values[ib]));
        continue;
      }
      if (!is_face) continue;
      for (size_t k = 0; k < e.properties.size(); ++k) {
        const std::string& name = e.properties[k].name;
        if (!e.properties[k].IsList() || (name != "vertex_indices" && name != "vertex_index"))
          continue;
        // Fan polygons into triangles (convex faces, as PLY writers produce).
        const std::vector<double>& ids = lists[k];
        for (size_t j = 2; j < ids.size(); ++j)
          mesh.faces.emplace_back(VertexIndex(ids[0], file), VertexIndex(ids[j - 1], file),
                                  VertexIndex(ids[j], file));
      }
    }
  }
  const int num_vertices = static_cast<int>(mesh.vertices.size());
  for (const Eigen::Vector3i& f : mesh.faces)
    if (f.minCoeff() < 0 || f.maxCoeff() >= num_vertices)
      Fail("{}: face index out of range", file.string());
  if (mesh.faces.empty()) Fail("{}: mesh has no faces", file.string());
  return mesh;
}

}  // namespace varsfm
