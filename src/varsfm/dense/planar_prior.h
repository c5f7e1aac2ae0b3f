#pragma once
// The planar prior of Xu & Tao, "Planar Prior Assisted PatchMatch Multi-View Stereo" (AAAI 2020,
// ACMP): the confident pixels of a first PatchMatch pass (low cost, confirmed by other views)
// are triangulated in the image (Delaunay), and each triangle's plane through its three 3D
// points is the prior of the pixels it covers. In weakly textured areas (a white wall, gravel
// seen at a grazing angle) the photometric cost is nearly flat over many wrong planes; the
// plane spanned by the textured pixels around such an area is the likely surface, and a second
// pass weighs it in (patchmatch.h, PatchMatchOptions::planar_weight).
#include <Eigen/Core>

#include "varsfm/dense/patchmatch.h"

namespace varsfm {

struct PlanarPriorOptions {
  int num_iterations = 0;           // sweeps of the planar-prior pass (0: no planar prior)
  double anchor_max_cost = 0.1;     // ACMP's "credible" pixels: cost below this
  int anchor_cell = 5;              // px: at most one anchor (the lowest cost) per cell
  double max_edge_fraction = 0.25;  // triangles with a longer side (x the image's longer side) go
  // Triangles whose plane is seen this close to edge-on at their centroid are left out: their
  // depth changes too fast across a pixel to be a prior.
  double max_view_angle_deg = 85.0;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

// The prior planes of a view: for every pixel inside a kept triangle of the anchors of `map`
// (depth > 0 and cost <= anchor_max_cost), the depth where its ray meets the triangle's plane
// and the plane's normal (camera frame, facing the camera); depth 0 elsewhere. `K` is the map's
// pinhole matrix. Deterministic.
DepthMap BuildPlanarPrior(const DepthMap& map, const Eigen::Matrix3d& K,
                          const PlanarPriorOptions& options);

}  // namespace varsfm
