#pragma once
// Reads a triangle mesh PLY (what `varsfm mesh` writes, and what MeshLab / Open3D / CGAL write):
// ascii or binary_little_endian; vertex x y z (any scalar type) with optional red green blue,
// face list vertex_indices (or vertex_index); polygons are fanned into triangles.
#include <filesystem>

#include "varsfm/mesh/triangle_mesh.h"

namespace varsfm {

// Throws varsfm::Error (one line naming the file) for a missing or malformed file, an index out
// of range, or a mesh without faces.
TriangleMesh ReadMeshPly(const std::filesystem::path& file);

}  // namespace varsfm
