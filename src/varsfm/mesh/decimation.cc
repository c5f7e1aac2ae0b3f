#include "varsfm/mesh/decimation.h"

#include <array>
#include <vector>

// GCC flags Eigen's fixed-size matrices inside CGAL's quadric code as maybe-uninitialised (a
// false positive of its inlining): silenced for these headers and their instantiation below.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_plane_policies.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;
namespace SMS = CGAL::Surface_mesh_simplification;

}  // namespace

void DecimationOptions::Check() const {
  // Fewer faces than a tetrahedron's leave no surface to texture.
  if (max_faces != 0) CheckInRange("--max-faces", max_faces, size_t{4}, size_t{1} << 31);
}

size_t DecimateMesh(const DecimationOptions& options, TriangleMesh* mesh) {
  const size_t before = mesh->faces.size();
  if (options.max_faces == 0 || before <= options.max_faces) return 0;
  std::vector<Point> points;
  points.reserve(mesh->vertices.size());
  for (const Eigen::Vector3d& v : mesh->vertices) points.emplace_back(v.x(), v.y(), v.z());
  std::vector<std::array<size_t, 3>> polygons;
  polygons.reserve(before);
  for (const Eigen::Vector3i& f : mesh->faces)
    polygons.push_back(
        {static_cast<size_t>(f[0]), static_cast<size_t>(f[1]), static_cast<size_t>(f[2])});
  // The visibility cut's surface can have non-manifold edges and vertices: the soup is repaired
  // and oriented (duplicating the vertices where sheets meet) before it becomes a halfedge mesh.
  PMP::repair_polygon_soup(points, polygons);
  PMP::orient_polygon_soup(points, polygons);
  SurfaceMesh sm;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, sm);

  // A triangle mesh has about 1.5 edges per face.
  const SMS::Count_stop_predicate<SurfaceMesh> stop(options.max_faces * 3 / 2);
  const SMS::GarlandHeckbert_plane_policies<SurfaceMesh, Kernel> policies(sm);
  SMS::edge_collapse(
      sm, stop,
      CGAL::parameters::get_cost(policies.get_cost()).get_placement(policies.get_placement()));
  sm.collect_garbage();

  TriangleMesh out;
  out.vertices.reserve(sm.number_of_vertices());
  for (const SurfaceMesh::Vertex_index v : sm.vertices()) {
    const Point& p = sm.point(v);
    out.vertices.emplace_back(p.x(), p.y(), p.z());
  }
  out.faces.reserve(sm.number_of_faces());
  for (const SurfaceMesh::Face_index f : sm.faces()) {
    Eigen::Vector3i face;
    int k = 0;
    for (const SurfaceMesh::Vertex_index v : CGAL::vertices_around_face(sm.halfedge(f), sm))
      if (k < 3) face[k++] = static_cast<int>(v.idx());
    if (k == 3) out.faces.push_back(face);
  }
  *mesh = std::move(out);
  return before - mesh->faces.size();
}

}  // namespace varsfm

#pragma GCC diagnostic pop
