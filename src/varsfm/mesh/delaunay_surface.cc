#include "varsfm/mesh/delaunay_surface.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include <Eigen/Geometry>

#include "varsfm/mesh/mesh_topology.h"
#include "varsfm/mesh/point_grid.h"
#include "varsfm/mesh/smoothing.h"
#include "varsfm/mesh/tetrahedra.h"
#include "varsfm/util/error.h"
#include "varsfm/util/graph_cut.h"
#include "varsfm/util/log.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/progress.h"
#include "varsfm/util/timer.h"

namespace varsfm {
namespace {

// Ray weights are summed as integers in units of 1/kUnits of a ray's weight, so the sums, and
// the cut, do not depend on the order in which threads add them.
constexpr double kUnits = 64.0;
// Infinite cells lie outside the convex hull of the points: outside for certain.
constexpr double kCertain = 1e12;

struct RayWeights {
  explicit RayWeights(size_t cells) : facet(4 * cells), source(cells), sink(cells) {}
  // facet[4 c + i]: rays that cross facet i of cell c into c (from the neighbour, the camera's
  // side); source[c]: rays whose camera lies in c; sink[c]: rays whose point lies sigma in
  // front of c.
  std::vector<std::atomic<uint32_t>> facet, source, sink;
};

void Add(std::atomic<uint32_t>& sum, double weight) {
  sum.fetch_add(static_cast<uint32_t>(std::lround(weight * kUnits)), std::memory_order_relaxed);
}

// Labatut et al. section 4.2: every ray camera -> point marks the cells it crosses as free (a
// weight on each facet it crosses, soft within a few sigma of the point) and the cell holding
// the camera as outside; the cells the ray would cross over sigma behind the point are inside
// (Labatut: the one at sigma; all of them, as Jancosek & Pajdla do, so that the thin cells
// right under a surface seen from one side are held inside too, not only a deeper one).
size_t AccumulateRays(const Tetrahedra& tets, const PointCloud& merged, double sigma,
                      RayWeights* weights) {
  std::atomic<size_t> rays{0};
  Progress progress("surface: rays", merged.points.size());
  const auto add_rays_of = [&](size_t i) {
    const uint32_t vertex = static_cast<uint32_t>(i);
    if (tets.incident_begin[i] == tets.incident_begin[i + 1]) return;  // a duplicate
    for (uint32_t view : merged.visibility[i]) {
      const Eigen::Vector3d to_camera = merged.viewpoints[view] - merged.points[i];
      const double length = to_camera.norm();
      if (!(length > 0)) continue;
      rays.fetch_add(1, std::memory_order_relaxed);
      WalkRay(tets, vertex, to_camera, 1.0, [&](const RayCell& step) {
        if (step.exit_facet >= 0) {
          const double d = step.t_exit * length / sigma;
          // Beyond d^2 = 10, exp(-d^2 / 2) < 1 / 128 and the weight rounds to a whole ray's units:
          // most facets a ray crosses lie there, so exp is skipped for them.
          Add(weights->facet[4 * step.cell + step.exit_facet],
              d * d > 10.0 ? 1.0 : 1.0 - std::exp(-0.5 * d * d));
        } else if (!tets.IsInfinite(step.cell)) {
          Add(weights->source[step.cell], 1.0);
        }
      });
      WalkRay(tets, vertex, -to_camera / length, sigma, [&](const RayCell& step) {
        if (!tets.IsInfinite(step.cell)) Add(weights->sink[step.cell], 1.0);
      });
    }
  };
  // Blocks of points, so that the progress (a lock per tick) stays out of the loop.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, merged.points.size(), 4096),
                    [&](const tbb::blocked_range<size_t>& block) {
                      for (size_t i = block.begin(); i != block.end(); ++i) add_rays_of(i);
                      progress.Tick(block.size());
                    });
  return rays.load();
}

// Per finite cell: cos of the angle between each facet's plane and the cell's circumsphere
// (|distance of the centre to the plane| / radius); 1 for a flat cell (centre at infinity).
std::vector<std::array<float, 4>> FacetSphereCosines(const Tetrahedra& tets) {
  std::vector<std::array<float, 4>> cosines(tets.cells.size(), {1, 1, 1, 1});
  tbb::parallel_for(size_t{0}, tets.cells.size(), [&](size_t c) {
    if (tets.IsInfinite(static_cast<uint32_t>(c))) return;
    const auto& v = tets.cells[c];
    const Eigen::Vector3d& a = tets.points[v[0]];
    const Eigen::Vector3d u = tets.points[v[1]] - a, w = tets.points[v[2]] - a,
                          x = tets.points[v[3]] - a;
    const double det = 2 * u.dot(w.cross(x));
    if (det == 0) return;
    const Eigen::Vector3d offset = (u.squaredNorm() * w.cross(x) + w.squaredNorm() * x.cross(u) +
                                    x.squaredNorm() * u.cross(w)) /
                                   det;
    const double radius = offset.norm();
    const Eigen::Vector3d centre = a + offset;
    for (int i = 0; i < 4; ++i) {
      const std::array<uint32_t, 3> f = tets.Facet(static_cast<uint32_t>(c), i);
      const Eigen::Vector3d& p = tets.points[f[0]];
      const Eigen::Vector3d normal = (tets.points[f[1]] - p).cross(tets.points[f[2]] - p);
      const double n = normal.norm();
      if (n == 0 || !(radius > 0)) continue;
      cosines[c][i] =
          static_cast<float>(std::min(1.0, std::abs(normal.dot(centre - p)) / (n * radius)));
    }
  });
  return cosines;
}

// The s-t graph over the cells (source: outside, sink: inside); true per cell when inside.
std::vector<bool> LabelCells(const Tetrahedra& tets, const RayWeights& weights,
                             double quality_weight) {
  const std::vector<std::array<float, 4>> cosines = FacetSphereCosines(tets);
  const size_t n = tets.cells.size();
  MinCut cut(n, 2 * n);  // a closed triangulation has two facets per cell
  for (uint32_t c = 0; c < n; ++c) {
    if (tets.IsInfinite(c)) {
      cut.SetTerminalWeights(c, kCertain, 0);
    } else {
      cut.SetTerminalWeights(c, weights.source[c].load() / kUnits, weights.sink[c].load() / kUnits);
    }
    for (int i = 0; i < 4; ++i) {
      const uint32_t m = tets.neighbors[c][i];
      if (m < c || (tets.IsInfinite(c) && tets.IsInfinite(m))) continue;
      const int j = tets.mirror[c][i];
      float cosine = 1;
      if (!tets.IsInfinite(c)) cosine = std::min(cosine, cosines[c][i]);
      if (!tets.IsInfinite(m)) cosine = std::min(cosine, cosines[m][j]);
      const double quality = quality_weight * (1.0 - cosine);
      // Rays entering c through this facet come from m: cutting m outside, c inside, blocks them.
      cut.AddEdge(m, c, weights.facet[4 * c + i].load() / kUnits + quality,
                  weights.facet[4 * m + j].load() / kUnits + quality);
    }
  }
  const std::vector<bool> outside = cut.Solve();
  std::vector<bool> inside(n);
  for (size_t c = 0; c < n; ++c)
    inside[c] = !outside[c] && !tets.IsInfinite(static_cast<uint32_t>(c));
  return inside;
}

// The facets between inside and outside cells, counter-clockwise seen from outside.
TriangleMesh ExtractSurface(const Tetrahedra& tets, const std::vector<bool>& inside) {
  TriangleMesh mesh;
  mesh.vertices = tets.points;
  for (uint32_t c = 0; c < tets.cells.size(); ++c) {
    if (!inside[c]) continue;
    for (int i = 0; i < 4; ++i) {
      if (inside[tets.neighbors[c][i]]) continue;
      const std::array<uint32_t, 3> f = tets.Facet(c, i);
      const Eigen::Vector3d& a = tets.points[f[0]];
      const Eigen::Vector3d normal = (tets.points[f[1]] - a).cross(tets.points[f[2]] - a);
      const bool towards_cell = normal.dot(tets.points[tets.cells[c][i]] - a) > 0;
      const Eigen::Vector3i face(static_cast<int>(f[0]), static_cast<int>(f[1]),
                                 static_cast<int>(f[2]));
      mesh.faces.push_back(towards_cell ? Eigen::Vector3i(face[0], face[2], face[1]) : face);
    }
  }
  return mesh;
}

// Removes the connected parts (faces sharing vertices) with fewer than min_fraction of the
// faces; returns how many faces went.
size_t RemoveSmallComponents(double min_fraction, TriangleMesh* mesh) {
  const std::vector<uint32_t> root = ComponentRoots(*mesh);
  std::vector<size_t> faces(root.size(), 0);
  for (const Eigen::Vector3i& f : mesh->faces) ++faces[root[f[0]]];
  const double min_faces = min_fraction * mesh->faces.size();
  const size_t before = mesh->faces.size();
  std::erase_if(mesh->faces,
                [&](const Eigen::Vector3i& f) { return faces[root[f[0]]] < min_faces; });
  return before - mesh->faces.size();
}

}  // namespace

void DelaunaySurfaceOptions::Check() const {
  CheckPositive("--merge-spacing", merge_spacing);
  if (max_merged_points != 0) CheckAtLeast("--max-merged-points", max_merged_points, size_t{10});
  CheckPositive("--sigma", sigma);
  CheckNonNegative("--quality-weight", quality_weight);
  long_faces.Check();
  CheckFraction("--min-component", min_component_fraction);
  CheckNonNegative("--smoothing", smoothing_iterations);
  hole_filling.Check();
}

TriangleMesh ReconstructDelaunaySurface(const PointCloud& cloud, double spacing,
                                        const DelaunaySurfaceOptions& options,
                                        DelaunaySurfaceStats* stats,
                                        const std::vector<PosedCamera>& views) {
  if (!cloud.HasVisibility())
    Fail(
        "the Delaunay surface needs the points' visibility (the cameras that saw each point); "
        "densify again to record it, or use --method poisson");
  DelaunaySurfaceStats local;
  DelaunaySurfaceStats& s = stats ? *stats : local;
  s = {};
  Timer timer;
  double voxel = options.merge_spacing * spacing;
  const PointCloud merged =
      options.max_merged_points > 0
          ? VoxelDownsampleAtMost(cloud, options.max_merged_points, voxel, &voxel)
          : VoxelDownsample(cloud, voxel);
  s.merged_points = merged.points.size();
  s.merge_voxel = voxel;
  if (voxel > options.merge_spacing * spacing)
    spdlog::info(
        "surface: points merged at {:.3g} x their spacing instead of {:.3g}, to keep at most {} "
        "merged points",
        voxel / spacing, options.merge_spacing, options.max_merged_points);
  spdlog::info("surface: Delaunay tetrahedralisation of {} merged points", s.merged_points);
  const Tetrahedra tets = Tetrahedralize(merged.points);
  s.cells = tets.cells.size();
  s.seconds_tetrahedra = timer.Seconds();
  timer.Restart();

  RayWeights weights(tets.cells.size());
  s.rays = AccumulateRays(tets, merged, options.sigma * voxel, &weights);
  s.seconds_rays = timer.Seconds();
  timer.Restart();

  spdlog::info("surface: minimum cut of {} cells", tets.cells.size());
  const std::vector<bool> inside = LabelCells(tets, weights, options.quality_weight);
  s.inside_cells = static_cast<size_t>(std::count(inside.begin(), inside.end(), true));
  TriangleMesh mesh = ExtractSurface(tets, inside);
  s.long_faces = RemoveLongFaces(options.long_faces, views, &mesh);
  s.removed_faces = RemoveSmallComponents(options.min_component_fraction, &mesh);
  s.holes = FillSmallHoles(options.hole_filling, &mesh);
  RemoveUnreferencedVertices(&mesh);
  TaubinSmooth(options.smoothing_iterations, &mesh);
  s.seconds_cut = timer.Seconds();
  spdlog::info(
      "surface: Delaunay of {} merged points ({} cells, {:.1f} s), {} rays ({:.1f} s), {} inside "
      "cells, {} faces ({} long faces, {} of them kept in enclosed holes; {} in small parts "
      "removed; {} of {} boundary loops filled with {} faces, {} of them refined and faired "
      "with {} new vertices; cut {:.1f} s)",
      s.merged_points, s.cells, s.seconds_tetrahedra, s.rays, s.seconds_rays, s.inside_cells,
      mesh.faces.size(), s.long_faces.long_faces, s.long_faces.kept, s.removed_faces,
      s.holes.filled_loops, s.holes.loops, s.holes.added_faces, s.holes.faired_loops,
      s.holes.added_vertices, s.seconds_cut);
  if (mesh.faces.empty()) Fail("the visibility cut labelled no tetrahedron inside: no surface");
  return mesh;
}

}  // namespace varsfm
