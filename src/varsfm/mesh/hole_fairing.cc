#include "varsfm/mesh/hole_fairing.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/fair.h>
#include <CGAL/Polygon_mesh_processing/refine.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/iterator.h>

#include <iterator>
#include <unordered_map>

namespace varsfm {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
using VertexIndex = SurfaceMesh::Vertex_index;
using FaceIndex = SurfaceMesh::Face_index;

}  // namespace

bool RefineAndFairPatch(const TriangleMesh& mesh, const std::vector<Eigen::Vector3i>& ring,
                        double density, std::vector<Eigen::Vector3i>* patch,
                        std::vector<Eigen::Vector3d>* new_vertices) {
  SurfaceMesh surface;
  std::unordered_map<int, VertexIndex> local;
  std::vector<int> global;  // per surface vertex: its mesh index
  const auto vertex = [&](int v) {
    const auto [it, inserted] = local.try_emplace(v);
    if (inserted) {
      const Eigen::Vector3d& p = mesh.vertices[v];
      it->second = surface.add_vertex(Kernel::Point_3(p.x(), p.y(), p.z()));
      global.push_back(v);
    }
    return it->second;
  };
  const auto add = [&](const Eigen::Vector3i& f) {
    return surface.add_face(vertex(f[0]), vertex(f[1]), vertex(f[2]));
  };
  // The patch first, a disc of its own; then the ring, leaving out a face that would make the
  // surface non-manifold (a flap on the rim, a pinch): the fairing then holds fewer neighbours of
  // that loop vertex fixed.
  std::vector<FaceIndex> patch_faces;
  for (const Eigen::Vector3i& f : *patch) {
    patch_faces.push_back(add(f));
    if (patch_faces.back() == SurfaceMesh::null_face()) return false;
  }
  for (const Eigen::Vector3i& f : ring) add(f);
  const size_t patch_and_ring = surface.number_of_faces();
  const size_t old_vertices = surface.number_of_vertices();

  std::vector<VertexIndex> added;
  namespace pmp = CGAL::Polygon_mesh_processing;
  pmp::refine(surface, patch_faces, CGAL::Emptyset_iterator(), std::back_inserter(added),
              CGAL::parameters::density_control_factor(density));
  // Thin-plate fairing (tangent continuity with the fixed ring, cotangent weights).
  if (!added.empty() && !pmp::fair(surface, added, CGAL::parameters::fairing_continuity(1)))
    return false;

  // Faces and vertices keep their indices through refinement and new ones are numbered after
  // them: the patch's faces are its original ones, first, and those after the ring's.
  const int first_new = static_cast<int>(mesh.vertices.size() + new_vertices->size());
  const auto index_of = [&](VertexIndex v) {
    const size_t i = v.idx();
    return i < old_vertices ? global[i] : first_new + static_cast<int>(i - old_vertices);
  };
  std::vector<Eigen::Vector3i> faces;
  for (const FaceIndex f : surface.faces()) {
    if (f.idx() >= patch->size() && f.idx() < patch_and_ring) continue;
    Eigen::Vector3i corners;
    int k = 0;
    for (const VertexIndex v : CGAL::vertices_around_face(surface.halfedge(f), surface))
      corners[k++] = index_of(v);
    faces.push_back(corners);
  }
  std::vector<Eigen::Vector3d> positions;
  for (size_t i = old_vertices; i < surface.number_of_vertices(); ++i) {
    const Kernel::Point_3& p = surface.point(VertexIndex(static_cast<uint32_t>(i)));
    positions.emplace_back(p.x(), p.y(), p.z());
    if (!positions.back().allFinite()) return false;
  }
  new_vertices->insert(new_vertices->end(), positions.begin(), positions.end());
  *patch = std::move(faces);
  return true;
}

}  // namespace varsfm
