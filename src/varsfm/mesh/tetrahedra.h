#pragma once
// The Delaunay tetrahedralisation of a point set (CGAL's Delaunay_triangulation_3) copied into
// flat arrays, and the walk of a ray through it: what the visibility surface
// (delaunay_surface.h) needs. The arrays are read-only once built, so threads walk rays at once
// (CGAL's own traversals mark cells in the triangulation and cannot be shared).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace varsfm {

struct Tetrahedra {
  static constexpr uint32_t kInfinite = UINT32_MAX;  // the vertex at infinity in `cells`
  std::vector<Eigen::Vector3d> points;               // the input points; vertex i is point i
  // cells[c]: four point indices (kInfinite for the vertex at infinity), positively oriented.
  std::vector<std::array<uint32_t, 4>> cells;
  // neighbors[c][i]: the cell across the facet opposite cells[c][i]; mirror[c][i]: the index of
  // that facet in the neighbour.
  std::vector<std::array<uint32_t, 4>> neighbors;
  std::vector<std::array<uint8_t, 4>> mirror;
  // The cells incident to point i: incident[incident_begin[i] .. incident_begin[i + 1]). Empty
  // for a point that duplicates an earlier one (it is no vertex).
  std::vector<uint32_t> incident_begin, incident;

  bool IsInfinite(uint32_t cell) const {
    const std::array<uint32_t, 4>& v = cells[cell];
    return v[0] == kInfinite || v[1] == kInfinite || v[2] == kInfinite || v[3] == kInfinite;
  }
  // The three point indices of facet i of `cell` (the vertex i left out).
  std::array<uint32_t, 3> Facet(uint32_t cell, int i) const {
    const std::array<uint32_t, 4>& v = cells[cell];
    return {v[(i + 1) % 4], v[(i + 2) % 4], v[(i + 3) % 4]};
  }
};

// Throws varsfm::Error for fewer than four points or points that span no volume.
Tetrahedra Tetrahedralize(const std::vector<Eigen::Vector3d>& points);

// One cell a ray passes through: entered at parameter t_enter, left at t_exit through facet
// `exit_facet` of `cell` (-1 when the walk ends in this cell: the ray's end lies in it, or the
// cell is infinite, i.e. the ray has left the convex hull).
struct RayCell {
  uint32_t cell;
  double t_enter, t_exit;
  int exit_facet;
};

// Walks the ray points[vertex] + t * direction, t in [0, t_max], from the vertex through the
// cells it crosses, calling visit(const RayCell&) for each in order. Facets are chosen by where
// the ray meets them (barycentric coordinates), the exit of a convex cell being the one facet
// the line meets inside besides the entry, so a ray along a degenerate configuration still
// moves on; the walk stops after max_steps cells. Nothing is visited for a point that is no
// vertex.
template <typename Visit>
void WalkRay(const Tetrahedra& tets, uint32_t vertex, const Eigen::Vector3d& direction,
             double t_max, Visit&& visit, int max_steps = 200000);

namespace tetrahedra_internal {
// Where the ray origin + t dir meets the triangle (a, b, c) (Moller & Trumbore 1997): t, and the
// smallest barycentric coordinate of the meeting point (negative outside; -inf when parallel).
// Inline: a ray's walk calls it three times per cell it crosses.
inline void IntersectTriangle(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                              const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                              const Eigen::Vector3d& c, double* t, double* inside) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a;
  const Eigen::Vector3d p = dir.cross(e2);
  const double det = e1.dot(p);
  if (det == 0 || !std::isfinite(det)) {
    *t = 0;
    *inside = -std::numeric_limits<double>::infinity();
    return;
  }
  const double inv = 1.0 / det;
  const Eigen::Vector3d s = origin - a;
  const double u = s.dot(p) * inv;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = dir.dot(q) * inv;
  *t = e2.dot(q) * inv;
  *inside = std::min({u, v, 1.0 - u - v});
}
// The finite cell incident to `vertex` whose facet opposite it the ray enters first, with that
// facet's index and parameter; false when the ray leaves the convex hull at the vertex.
bool FirstCell(const Tetrahedra& tets, uint32_t vertex, const Eigen::Vector3d& direction,
               uint32_t* cell, int* facet, double* t);
}  // namespace tetrahedra_internal

template <typename Visit>
void WalkRay(const Tetrahedra& tets, uint32_t vertex, const Eigen::Vector3d& direction,
             double t_max, Visit&& visit, int max_steps) {
  using tetrahedra_internal::IntersectTriangle;
  uint32_t cell;
  int exit;
  double t_exit;
  if (!tetrahedra_internal::FirstCell(tets, vertex, direction, &cell, &exit, &t_exit)) return;
  const Eigen::Vector3d& origin = tets.points[vertex];
  double t_enter = 0;
  for (int step = 0; step < max_steps; ++step) {
    if (t_exit >= t_max) {
      visit(RayCell{cell, t_enter, t_max, -1});
      return;
    }
    visit(RayCell{cell, t_enter, t_exit, exit});
    const uint32_t next = tets.neighbors[cell][exit];
    const int entry = tets.mirror[cell][exit];
    if (tets.IsInfinite(next)) {
      visit(RayCell{next, t_exit, t_max, -1});
      return;
    }
    cell = next;
    t_enter = t_exit;
    double best = -std::numeric_limits<double>::infinity();
    for (int j = 0; j < 4; ++j) {
      if (j == entry) continue;
      const std::array<uint32_t, 3> f = tets.Facet(cell, j);
      double t, inside;
      IntersectTriangle(origin, direction, tets.points[f[0]], tets.points[f[1]], tets.points[f[2]],
                        &t, &inside);
      if (inside > best) best = inside, exit = j, t_exit = std::max(t, t_enter);
    }
  }
}

}  // namespace varsfm
