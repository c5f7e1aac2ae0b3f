#include "varsfm/mesh/advancing_front.h"

#include <algorithm>
#include <array>
#include <iterator>
#include <utility>

#include <CGAL/Advancing_front_surface_reconstruction.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <Eigen/Geometry>

#include "varsfm/mesh/mesh_topology.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalPoint = Kernel::Point_3;

CgalPoint ToCgal(const Eigen::Vector3d& p) { return {p.x(), p.y(), p.z()}; }

}  // namespace

TriangleMesh ReconstructAdvancingFront(const PointCloud& cloud) {
  std::vector<CgalPoint> points;
  points.reserve(cloud.points.size());
  for (const auto& p : cloud.points) points.push_back(ToCgal(p));
  std::vector<std::array<std::size_t, 3>> facets;
  CGAL::advancing_front_surface_reconstruction(points.begin(), points.end(),
                                               std::back_inserter(facets));
  if (facets.empty()) Fail("advancing-front surface reconstruction produced no faces");
  // CGAL gives the same faces in an order that follows the heap's layout (two calls in one
  // process differ): each face starts at its smallest index, orientation kept, and the faces
  // are sorted, so that the mesh is the same whenever the points are.
  for (auto& f : facets) std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
  std::sort(facets.begin(), facets.end());
  TriangleMesh mesh;
  mesh.vertices = cloud.points;
  for (const auto& f : facets) {
    mesh.faces.emplace_back(static_cast<int>(f[0]), static_cast<int>(f[1]), static_cast<int>(f[2]));
  }
  // Orient faces like the input normals (advancing front orients consistently, but its global
  // sign is arbitrary).
  if (cloud.HasNormals()) {
    double agreement = 0;
    for (const Eigen::Vector3i& f : mesh.faces) {
      const Eigen::Vector3d n = (mesh.vertices[f[1]] - mesh.vertices[f[0]])
                                    .cross(mesh.vertices[f[2]] - mesh.vertices[f[0]]);
      agreement += n.dot(cloud.normals[f[0]] + cloud.normals[f[1]] + cloud.normals[f[2]]);
    }
    if (agreement < 0) {
      for (Eigen::Vector3i& f : mesh.faces) std::swap(f[1], f[2]);
    }
  }
  RemoveUnreferencedVertices(&mesh);
  return mesh;
}

}  // namespace varsfm
