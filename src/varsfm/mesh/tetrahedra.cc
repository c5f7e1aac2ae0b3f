#include "varsfm/mesh/tetrahedra.h"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <cmath>
#include <utility>

#include <Eigen/Geometry>

#include "varsfm/util/error.h"

namespace varsfm {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_3<uint32_t, Kernel>;
using CellBase = CGAL::Triangulation_cell_base_with_info_3<uint32_t, Kernel>;
using DataStructure = CGAL::Triangulation_data_structure_3<VertexBase, CellBase>;
using Delaunay = CGAL::Delaunay_triangulation_3<Kernel, DataStructure>;

}  // namespace

namespace tetrahedra_internal {

bool FirstCell(const Tetrahedra& tets, uint32_t vertex, const Eigen::Vector3d& direction,
               uint32_t* cell, int* facet, double* t) {
  const Eigen::Vector3d& origin = tets.points[vertex];
  double best = -std::numeric_limits<double>::infinity();
  for (uint32_t k = tets.incident_begin[vertex]; k < tets.incident_begin[vertex + 1]; ++k) {
    const uint32_t c = tets.incident[k];
    if (tets.IsInfinite(c)) continue;
    int i = 0;
    while (tets.cells[c][i] != vertex) ++i;
    const std::array<uint32_t, 3> f = tets.Facet(c, i);
    double tc, inside;
    IntersectTriangle(origin, direction, tets.points[f[0]], tets.points[f[1]], tets.points[f[2]],
                      &tc, &inside);
    if (tc > 0 && inside > best) best = inside, *cell = c, *facet = i, *t = tc;
  }
  // Outside every finite cell's cone by more than rounding: the ray leaves the hull here.
  return best > -1e-6;
}

}  // namespace tetrahedra_internal

Tetrahedra Tetrahedralize(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < 4) Fail("{} points are too few for a tetrahedralisation", points.size());
  if (points.size() >= Tetrahedra::kInfinite) Fail("{} points are too many", points.size());
  std::vector<std::pair<Kernel::Point_3, uint32_t>> input;
  input.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i)
    input.emplace_back(Kernel::Point_3(points[i].x(), points[i].y(), points[i].z()),
                       static_cast<uint32_t>(i));
  // The range insertion sorts the points along a Hilbert curve (with a fixed seed), so the
  // triangulation, and the cell order below, are the same on every run.
  const Delaunay dt(input.begin(), input.end());
  if (dt.dimension() < 3) Fail("the points span no volume (all on a plane or a line)");

  Tetrahedra tets;
  tets.points = points;
  uint32_t next = 0;
  for (auto c = dt.all_cells_begin(); c != dt.all_cells_end(); ++c) c->info() = next++;
  tets.cells.resize(next);
  tets.neighbors.resize(next);
  tets.mirror.resize(next);
  std::vector<uint32_t> count(points.size() + 1, 0);
  for (auto c = dt.all_cells_begin(); c != dt.all_cells_end(); ++c) {
    const uint32_t id = c->info();
    for (int i = 0; i < 4; ++i) {
      const auto v = c->vertex(i);
      tets.cells[id][i] = dt.is_infinite(v) ? Tetrahedra::kInfinite : v->info();
      tets.neighbors[id][i] = c->neighbor(i)->info();
      tets.mirror[id][i] = static_cast<uint8_t>(dt.mirror_index(c, i));
      if (!dt.is_infinite(v)) ++count[v->info() + 1];
    }
  }
  tets.incident_begin.assign(points.size() + 1, 0);
  for (size_t i = 0; i < points.size(); ++i)
    tets.incident_begin[i + 1] = tets.incident_begin[i] + count[i + 1];
  tets.incident.resize(tets.incident_begin.back());
  std::vector<uint32_t> fill(tets.incident_begin.begin(), tets.incident_begin.end() - 1);
  for (uint32_t c = 0; c < next; ++c)
    for (uint32_t v : tets.cells[c])
      if (v != Tetrahedra::kInfinite) tets.incident[fill[v]++] = c;
  return tets;
}

}  // namespace varsfm
