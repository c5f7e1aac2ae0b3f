#pragma once
// The topology of a triangle mesh (is it manifold, is it closed, its connected parts) and its
// clean-up.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "varsfm/scene/triangle_mesh.h"

namespace varsfm {

struct EdgeTopology {
  size_t num_edges = 0;
  size_t boundary_edges = 0;      // used by exactly one face
  size_t non_manifold_edges = 0;  // used by more than two faces
};

// Counts undirected edges by how many faces use them: a manifold (possibly open) surface has
// non_manifold_edges == 0; a closed one also has boundary_edges == 0.
EdgeTopology ComputeEdgeTopology(const TriangleMesh& mesh);

// Per vertex: the smallest vertex index of its connected part (faces sharing vertices; a vertex
// in no face is its own part). Union-find with path halving.
std::vector<uint32_t> ComponentRoots(const TriangleMesh& mesh);

// Per vertex: its edge neighbours, sorted and unique (so sums over them run in a fixed order).
std::vector<std::vector<int>> VertexNeighbours(const TriangleMesh& mesh);

// Drops vertices no face references and renumbers the faces.
void RemoveUnreferencedVertices(TriangleMesh* mesh);

}  // namespace varsfm
