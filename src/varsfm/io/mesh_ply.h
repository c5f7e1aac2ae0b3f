#pragma once
// Triangle meshes as PLY. Written: binary little-endian, vertex x y z float, red green blue
// uchar, face list uchar int vertex_indices (the layout MeshLab and Blender read). Read: what
// `varsfm mesh` writes and what MeshLab / Open3D / CGAL write: ascii or binary_little_endian;
// vertex x y z (any scalar type) with optional red green blue, face list vertex_indices (or
// vertex_index); polygons are fanned into triangles.
#include <filesystem>

#include "varsfm/scene/triangle_mesh.h"

namespace varsfm {

// Writes atomically (temporary file, then rename). Throws varsfm::Error naming the file when it
// cannot be written or when colours/faces do not match the vertices.
void WriteMeshPly(const std::filesystem::path& file, const TriangleMesh& mesh);

// Throws varsfm::Error (one line naming the file) for a missing or malformed file, an index out
// of range, or a mesh without faces.
TriangleMesh ReadMeshPly(const std::filesystem::path& file);

}  // namespace varsfm
