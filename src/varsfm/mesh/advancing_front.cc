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
  TriangleMesh mesh;
  mesh.vertices = cloud.points;
  for (const auto& f : facets) {
    mesh.faces.emplace_back(static_cast<int>(f[0]), static_cast<int>(f[1]), static_cast<int>(f[2]));
  }
  // CGAL gives the same faces in an order, and a global orientation, that follow the heap's
  // layout (two calls in one process differ). Each face starts at its smallest index
  // (orientation kept), the faces are put in an order that ignores orientation, then oriented
  // like the input normals, or without normals like the first face, and sorted: the mesh is the
  // same whenever the points are.
  for (Eigen::Vector3i& f : mesh.faces) {
    int first = 0;
    if (f[1] < f[first]) first = 1;
    if (f[2] < f[first]) first = 2;
    f = Eigen::Vector3i(f[first], f[(first + 1) % 3], f[(first + 2) % 3]);
  }
  const auto unoriented = [](const Eigen::Vector3i& f) {
    return std::array<int, 3>{f[0], std::min(f[1], f[2]), std::max(f[1], f[2])};
  };
  std::sort(mesh.faces.begin(), mesh.faces.end(),
            [&](const Eigen::Vector3i& a, const Eigen::Vector3i& b) {
              const std::array<int, 3> key_a = unoriented(a), key_b = unoriented(b);
              return key_a != key_b ? key_a < key_b : a[1] < b[1];  // a face twice: both ways
            });
  bool flip = mesh.faces.front()[1] > mesh.faces.front()[2];
  if (cloud.HasNormals()) {
    double agreement = 0;
    for (const Eigen::Vector3i& f : mesh.faces) {
      const Eigen::Vector3d n = (mesh.vertices[f[1]] - mesh.vertices[f[0]])
                                    .cross(mesh.vertices[f[2]] - mesh.vertices[f[0]]);
      agreement += n.dot(cloud.normals[f[0]] + cloud.normals[f[1]] + cloud.normals[f[2]]);
    }
    flip = agreement < 0;
  }
  if (flip)
    for (Eigen::Vector3i& f : mesh.faces) std::swap(f[1], f[2]);
  RemoveUnreferencedVertices(&mesh);
  return mesh;
}

}  // namespace varsfm
