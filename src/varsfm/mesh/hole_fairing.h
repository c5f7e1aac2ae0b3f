#pragma once
// Refining and fairing the patch that closes a hole (Liepa, "Filling holes in meshes", SGP 2003,
// secs. 4.2-4.3, through CGAL's refine and fair). The triangulation over the loop's own vertices
// (hole_filling.h) is flat, and coarse where the hole is wide: a hole across a curved object (a
// puppet's torso) is spanned by a few large facets inside the true surface, and the photos
// project onto them what lies in front. New vertices at the density of the surface around the
// loop, placed to minimise a thin-plate energy with the faces around the loop held fixed, let the
// patch continue the surface's curvature and tangent planes across the hole.
#include <vector>

#include <Eigen/Core>

#include "varsfm/scene/triangle_mesh.h"

namespace varsfm {

// `patch`: the faces closing one hole, over mesh vertices, oriented like the faces around it;
// `ring`: the mesh's faces that touch the loop's vertices (held fixed). On success the patch is
// replaced by its refined faces, which may use new vertices numbered from mesh.vertices.size()
// on, whose positions are appended to `new_vertices` (the caller adds them to the mesh in that
// order). Returns false, leaving both untouched, where the ring and patch do not form a manifold
// surface (a pinch or a flap at the loop) or the fairing system has no solution.
bool RefineAndFairPatch(const TriangleMesh& mesh, const std::vector<Eigen::Vector3i>& ring,
                        double density, std::vector<Eigen::Vector3i>* patch,
                        std::vector<Eigen::Vector3d>* new_vertices);

}  // namespace varsfm
