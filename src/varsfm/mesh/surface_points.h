#pragma once
// The checks every surface method's input passes first (surface.h): a cloud with no spatial
// extent, far outliers and a cloud spread over far more than its point spacing break them all
// in the same places, so they are refused or dropped once, before any grid, octree or
// tetrahedralisation.
//
// Why: identical points give a zero spacing, on which screened Poisson's octree crashes and the
// advancing front's downsampling never ends; a few points at 1e30 make the Delaunay surface's
// ray walks (tetrahedra.h) cross slivers a whole cloud wide whose intersections are rounding
// noise, so each ray runs its full step budget (hours for a cloud that takes seconds).
#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "varsfm/scene/point_cloud.h"

namespace varsfm {

// Where the bulk of a cloud lies: its per-axis median and RobustExtent (mesh_quality.h, the
// diagonal of the 5th-95th percentile box), neither moved by a few far outliers.
struct RobustBounds {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double extent = 0;
};
RobustBounds MeasureRobustBounds(const std::vector<Eigen::Vector3d>& points);

// Throws varsfm::Error when the bulk of the points is (nearly) one point: a robust extent below
// 1e-6 of the centre's largest coordinate (about 16 steps of a float, the precision of a PLY's
// coordinates, of the mesh written and of Open3D's octree) or below 1e-30 absolutely.
void CheckSpatialExtent(const RobustBounds& bounds, size_t num_points);

// Points farther from bounds.centre than this many robust extents are dropped as outliers. The
// extent spans 90 % of the points on each axis, so a scene part 100 extents away is no part of
// the scene the photos show (a depth error, or a corrupt value), while everything a surface
// might use is kept.
inline constexpr double kFarPointExtents = 100;

// `cloud` without the points farther than kFarPointExtents x bounds.extent from bounds.centre,
// with a warning counting them; nullopt when there are none (the cloud is used as it is).
std::optional<PointCloud> WithoutFarPoints(const PointCloud& cloud, const RobustBounds& bounds);

// The points' bounding box may span at most this many average spacings: beyond, neighbouring
// points are a few float steps apart (a float resolves 2^-24 ~ 6e-8 of its magnitude), so the
// spacing is rounding noise, and what is left after WithoutFarPoints is two clusters far apart
// (half the points at 1e30).
inline constexpr double kMaxSpacingsAcross = 1e7;

// Throws varsfm::Error when `spacing` (AverageNearestSpacing of `points`) is not positive (the
// sampled points all have a twin) or the points span more than kMaxSpacingsAcross spacings.
void CheckPointSpacing(const std::vector<Eigen::Vector3d>& points, double spacing);

}  // namespace varsfm
