#pragma once
// Surface reconstruction from a dense point cloud. Default: the visibility-based Delaunay surface
// (delaunay_surface.h): the points tetrahedralised, each tetrahedron labelled inside or outside
// by a graph cut weighted by the rays camera -> point, so that it does not close over the sky or
// weakly textured space; it needs the cameras that saw each point (surface_input.h). The
// held-out views that chose it: bench/results/2026-12-03-surface-patchmatch.md. Selectable:
// screened Poisson (Kazhdan & Hoppe 2013, screened_poisson.h) at an octree depth chosen from the
// cloud's size over its point spacing, on every point, then trimmed where the surface leaves the
// data (by the sampling density the reconstruction reports and by the distance to the nearest
// point); advancing front (advancing_front.h). Every result passes the mesh check
// (mesh_quality.h) or the reconstruction fails with one line.
//
// CGAL's Poisson (the 2006 method), the former default, is gone: it crashed in
// facets_in_complex_2_to_triangle_mesh on bundler/kermit's cloud, and on the outdoor clouds of
// bundler/ET and sceaux it returned 116 and 155 faces from 322k and 1.04M points (its surface
// mesher starts from one inner point of the implicit function and meshes what it reaches from
// there). It also needed the cloud cut to 60,000 points to run in time.
#include <string>
#include <vector>

#include "varsfm/mesh/decimation.h"
#include "varsfm/mesh/delaunay_surface.h"
#include "varsfm/mesh/mesh_quality.h"
#include "varsfm/scene/point_cloud.h"
#include "varsfm/scene/triangle_mesh.h"
#include "varsfm/util/enum_names.h"

namespace varsfm {

enum class SurfaceMethod { kScreenedPoisson, kAdvancingFront, kDelaunay };

struct SurfaceOptions {
  SurfaceMethod method = SurfaceMethod::kDelaunay;
  // Screened Poisson: the finest octree cells are about cell_spacing x the average point
  // spacing, so a finest cell holds about cell_spacing^2 samples of the surface: Kazhdan's
  // guidance for noisy samples is 15-20 samples per node (1-5 for noise-free ones), and dense
  // points from photographs are noisy at their own spacing (fountain-P11: a median 0.0019 from
  // the local sparse plane at a spacing of 0.0028). The depth is clamped to [min_depth,
  // max_depth]: max_depth bounds memory and time (the octree's node count grows ~4x per level).
  double cell_spacing = 4.0;
  int min_depth = 6;
  int max_depth = 12;
  // Screened Poisson: vertices whose estimated sampling depth (screened_poisson.h) is more than
  // this many levels below the octree depth, i.e. where samples are 2^this times sparser than
  // at the finest cells, are removed with their faces: there the surface is interpolated over
  // missing data.
  double density_trim_levels = 3.0;
  // Threads of the screened Poisson solver. Its parallel reductions sum in an order that
  // depends on the thread count, so the mesh is bit-for-bit reproducible only for a fixed count.
  int num_threads = 1;
  // Advancing front only: voxel-grid downsampling above this many points (its Delaunay
  // triangulation's cost grows quickly with the point count).
  size_t max_points = 60000;
  // Screened Poisson: faces with a vertex farther than trim_factor x the average point spacing
  // from every input point are removed, so the closed implicit surface does not balloon over
  // holes. <= 0 keeps the whole surface.
  double trim_factor = 3.0;
  DelaunaySurfaceOptions delaunay;
  // Any method's surface, last: decimated to a face budget (0: none; decimation.h).
  DecimationOptions decimation;
  MeshQualityLimits quality;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

struct SurfaceStats {
  size_t input_points = 0;
  size_t used_points = 0;  // after merging (Delaunay) or downsampling (advancing front)
  double average_spacing = 0;
  int depth = 0;  // screened Poisson's octree depth
  DelaunaySurfaceStats delaunay;
  size_t faces_before_trim = 0;
  size_t decimated_faces = 0;  // removed by decimation
  // Of the final mesh against the points (without far outliers); the check judged the mesh
  // before decimation.
  MeshQuality quality;
};

// `options` must have passed Check() (the mesh stage checks them once, where it starts). Points
// far from the bulk of the cloud are dropped first, with a warning (surface_points.h). Throws
// varsfm::Error when the cloud has too few points, lacks normals (Poisson), has no spatial
// extent or spans far more than its spacing (surface_points.h), the reconstruction fails, or the
// mesh before decimation fails the check. Vertex colours come from the nearest input point when
// it has colours.
// `views`: the registered cameras, which judge the Delaunay surface's long faces (long_faces.h).
TriangleMesh ReconstructSurface(const PointCloud& cloud, const SurfaceOptions& options,
                                SurfaceStats* stats = nullptr,
                                const std::vector<PosedCamera>& views = {});

// The names the command line takes (`--method`, `--surface`), the default first.
inline constexpr EnumName<SurfaceMethod> kSurfaceMethodNames[] = {
    {SurfaceMethod::kDelaunay, "delaunay"},
    {SurfaceMethod::kScreenedPoisson, "poisson"},
    {SurfaceMethod::kAdvancingFront, "afront"}};
// Throws varsfm::Error naming the choices for a name that is none of them.
inline SurfaceMethod ParseSurfaceMethod(const std::string& name) {
  return ValueOf(kSurfaceMethodNames, name, "surface method");
}

}  // namespace varsfm
