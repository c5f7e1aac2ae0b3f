#pragma once
// Indexed triangle mesh with per-vertex colours, written as binary PLY (vertex x y z float,
// red green blue uchar; face list uchar int vertex_indices), the layout MeshLab and Blender read.
#include <cstdint>
#include <filesystem>
#include <vector>

#include <Eigen/Core>

namespace varsfm {

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Matrix<uint8_t, 3, 1>> colors;  // empty, or one per vertex
  std::vector<Eigen::Vector3i> faces;                // counter-clockwise seen from outside
};

// Writes atomically (temporary file, then rename). Throws varsfm::Error naming the file when it
// cannot be written or when colours/faces do not match the vertices.
void WriteMeshPly(const std::filesystem::path& file, const TriangleMesh& mesh);

struct EdgeTopology {
  size_t num_edges = 0;
  size_t boundary_edges = 0;      // used by exactly one face
  size_t non_manifold_edges = 0;  // used by more than two faces
};

// Counts undirected edges by how many faces use them: a manifold (possibly open) surface has
// non_manifold_edges == 0; a closed one also has boundary_edges == 0.
EdgeTopology ComputeEdgeTopology(const TriangleMesh& mesh);

// Drops vertices no face references and renumbers the faces.
void RemoveUnreferencedVertices(TriangleMesh* mesh);

}  // namespace varsfm
