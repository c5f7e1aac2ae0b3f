#include "varsfm/mesh/surface_points.h"

#include <algorithm>
#include <cmath>

#include "varsfm/mesh/mesh_quality.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"
#include "varsfm/util/statistics.h"

namespace varsfm {

RobustBounds MeasureRobustBounds(const std::vector<Eigen::Vector3d>& points) {
  RobustBounds bounds;
  if (points.empty()) return bounds;
  std::vector<double> coordinate(points.size());
  for (int axis = 0; axis < 3; ++axis) {
    for (size_t i = 0; i < points.size(); ++i) coordinate[i] = points[i][axis];
    bounds.centre[axis] = Median(coordinate);
  }
  bounds.extent = RobustExtent(points);
  return bounds;
}

void CheckSpatialExtent(const RobustBounds& bounds, size_t num_points) {
  const double magnitude = bounds.centre.cwiseAbs().maxCoeff();
  if (bounds.extent > 1e-6 * magnitude && bounds.extent > 1e-30) return;
  Fail(
      "the points have no spatial extent: the bulk of the {} spans {:.3g} around ({:.6g}, "
      "{:.6g}, {:.6g}), below a float's precision there (all (nearly) one point; a cloud far "
      "from the origin, georeferenced, needs shifting near it first)",
      num_points, bounds.extent, bounds.centre.x(), bounds.centre.y(), bounds.centre.z());
}

std::optional<PointCloud> WithoutFarPoints(const PointCloud& cloud, const RobustBounds& bounds) {
  const double limit = kFarPointExtents * bounds.extent;
  std::vector<size_t> keep;
  keep.reserve(cloud.points.size());
  for (size_t i = 0; i < cloud.points.size(); ++i)
    if ((cloud.points[i] - bounds.centre).norm() <= limit) keep.push_back(i);
  if (keep.size() == cloud.points.size()) return std::nullopt;
  spdlog::warn(
      "surface: {} of {} points lie more than {:.0f} x the cloud's extent {:.4g} from its median "
      "and are dropped as outliers",
      cloud.points.size() - keep.size(), cloud.points.size(), kFarPointExtents, bounds.extent);
  PointCloud near;
  near.viewpoints = cloud.viewpoints;
  for (const size_t i : keep) {
    near.points.push_back(cloud.points[i]);
    if (cloud.HasNormals()) near.normals.push_back(cloud.normals[i]);
    if (cloud.HasColors()) near.colors.push_back(cloud.colors[i]);
    if (cloud.HasVisibility()) near.visibility.push_back(cloud.visibility[i]);
  }
  return near;
}

void CheckPointSpacing(const std::vector<Eigen::Vector3d>& points, double spacing) {
  if (!(spacing > 0))
    Fail("the points have no spacing: every sampled point has a twin at the same place");
  Eigen::Vector3d lo = points[0], hi = points[0];
  for (const Eigen::Vector3d& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double across = (hi - lo).norm() / spacing;
  if (across > kMaxSpacingsAcross)
    Fail(
        "the points span {:.4g} but lie a mean {:.4g} apart ({:.3g} spacings across, at most "
        "{:.0e}): far outliers, or a spacing below a float's precision",
        (hi - lo).norm(), spacing, across, kMaxSpacingsAcross);
}

}  // namespace varsfm
