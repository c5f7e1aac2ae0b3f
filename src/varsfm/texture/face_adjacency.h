#pragma once
// Faces that share an edge: the neighbourhood for smoothing the view labelling and for growing
// charts of connected faces.
#include <array>
#include <vector>

#include <Eigen/Core>

namespace varsfm {

// For each face, the faces across its edges (v0 v1, v1 v2, v2 v0); -1 for a boundary edge. On a
// non-manifold edge (more than two faces) only the first two faces found are linked.
std::vector<std::array<int, 3>> FaceNeighbours(const std::vector<Eigen::Vector3i>& faces);

}  // namespace varsfm
