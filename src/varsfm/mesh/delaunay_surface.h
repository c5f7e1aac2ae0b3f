#pragma once
// A visibility-based surface (Labatut, Pons & Keriven, "Robust and efficient surface
// reconstruction from range data", CGF 2009; Jancosek & Pajdla, "Multi-view reconstruction
// preserving weakly-supported surfaces", CVPR 2011): the dense points are tetrahedralised
// (Delaunay, tetrahedra.h), every tetrahedron is labelled inside or outside by an s-t minimum cut
// (util/graph_cut.h), and the surface is the set of facets between inside and outside tetrahedra.
// The cut's weights come from the rays camera -> point of every observation: the space a ray
// crosses before its point is free (outside), the space just behind the point is matter
// (inside), and a surface-quality term prefers facets that lie along the sampled surface. No
// implicit function is fitted, so the surface does not close over the sky or weakly textured
// regions: where no ray says otherwise, space stays empty, and every vertex is a (merged, then
// smoothed) data point.
#include <cstddef>

#include <vector>

#include "varsfm/mesh/hole_filling.h"
#include "varsfm/mesh/long_faces.h"
#include "varsfm/scene/point_cloud.h"
#include "varsfm/scene/triangle_mesh.h"

namespace varsfm {

struct DelaunaySurfaceOptions {
  // Points within merge_spacing x the cloud's average spacing merge (a voxel grid; their
  // visibility is united) before the tetrahedralisation. The cut's graph has about six cells
  // per point, and neighbouring dense points from different image pairs differ mostly by depth
  // noise, so merging costs little detail and keeps the graph to a size set by the scene.
  double merge_spacing = 2.0;
  // At most this many merged points (0: no cap): where merge_spacing leaves more, the voxel
  // grows until they fit (point_grid.h). The tetrahedralisation and the cut take ~1.5 KB a
  // merged point, so a cloud of a thousand photos can outgrow memory; `varsfm mesh` sets the cap
  // from the usable memory (pipeline/mesh.h has the measured figures).
  size_t max_merged_points = 0;
  // sigma of Labatut et al. (section 4.2), in merged voxels: a ray's free-space weight rises
  // from 0 at its point to the full weight over a few sigma (1 - exp(-d^2 / 2 sigma^2)), so
  // points displaced by noise do not carve each other's surface; the tetrahedron sigma behind
  // the point gets the inside weight.
  double sigma = 0.5;
  // lambda of the surface-quality term (section 4.3) against a ray's weight of 1: each facet
  // costs lambda (1 - min(cos phi, cos psi)), phi and psi the angles between the facet and the
  // circumspheres of its two tetrahedra.
  double quality_weight = 1.0;
  // The long faces (long_faces.h): removed (optionally but those the views see fill holes the
  // surface encloses); the small holes left are filled (hole_filling below).
  LongFaceOptions long_faces;
  // Taubin lambda|mu passes (smoothing.h) over the surface: its vertices are dense points and
  // carry their depth noise. 0: the vertices stay on the data. 0 to 40 passes render held-out
  // views within 0.1 dB of each other on average (bench/results/2026-12-07-s37-smoothing.md).
  int smoothing_iterations = 10;
  // Connected parts of the surface with fewer faces than this fraction of the whole are
  // removed (floaters: a few tetrahedra labelled inside around a cluster of outliers).
  double min_component_fraction = 0.005;
  // The holes the cut and the long-face removal leave (hole_filling.h): loops of up to 100
  // edges, and no longer than 100 median edges, are closed.
  HoleFillingOptions hole_filling{.max_edges = 100};

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

struct DelaunaySurfaceStats {
  size_t merged_points = 0;
  double merge_voxel = 0;  // the voxel the points were merged in
  size_t cells = 0;
  size_t rays = 0;
  size_t inside_cells = 0;
  LongFaceStats long_faces;
  size_t removed_faces = 0;  // in small components
  HoleFillingStats holes;
  double seconds_tetrahedra = 0, seconds_rays = 0, seconds_cut = 0;
};

// `spacing`: the cloud's average point spacing (AverageNearestSpacing); `options` must have
// passed Check() (SurfaceOptions::Check, where the mesh stage starts); `views`: the registered
// cameras that judge the long faces (none: every long face is removed). Throws varsfm::Error
// when the cloud has no visibility, too few points, or the cut leaves no surface. Deterministic
// for any thread count (the rays' weights are summed in integers).
TriangleMesh ReconstructDelaunaySurface(const PointCloud& cloud, double spacing,
                                        const DelaunaySurfaceOptions& options,
                                        DelaunaySurfaceStats* stats = nullptr,
                                        const std::vector<PosedCamera>& views = {});

}  // namespace varsfm
