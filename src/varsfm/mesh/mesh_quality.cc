#include "varsfm/mesh/mesh_quality.h"

#include <algorithm>
#include <cmath>

#include "varsfm/util/error.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/statistics.h"

namespace varsfm {
namespace {

double Percentile(std::vector<double> values, double fraction) {
  const auto at = values.begin() + static_cast<ptrdiff_t>(fraction * (values.size() - 1));
  std::nth_element(values.begin(), at, values.end());
  return *at;
}

}  // namespace

void MeshQualityLimits::Check() const {
  CheckInHalfOpenRange("quality.max_relative_distance", max_relative_distance, 0, 1);
  CheckFraction("quality.min_faces_per_point", min_faces_per_point);
}

double RobustExtent(const std::vector<Eigen::Vector3d>& points) {
  if (points.empty()) return 0;
  Eigen::Vector3d size;
  std::vector<double> coordinate(points.size());
  for (int axis = 0; axis < 3; ++axis) {
    for (size_t i = 0; i < points.size(); ++i) coordinate[i] = points[i][axis];
    size[axis] = Percentile(coordinate, 0.95) - Percentile(coordinate, 0.05);
  }
  return size.norm();
}

MeshQuality MeasureMeshQuality(const TriangleMesh& mesh, const NearestPoints& cloud,
                               double spacing) {
  const std::vector<Eigen::Vector3d>& points = cloud.points();
  MeshQuality quality;
  quality.spacing = spacing;
  quality.num_points = points.size();
  quality.num_vertices = mesh.vertices.size();
  quality.num_faces = mesh.faces.size();
  quality.extent = RobustExtent(points);
  if (points.empty() || mesh.vertices.empty()) return quality;
  quality.median_distance = Median(cloud.DistancesTo(mesh.vertices));
  return quality;
}

void CheckMeshQuality(const MeshQuality& quality, const MeshQualityLimits& limits) {
  const double min_faces = limits.min_faces_per_point * quality.num_points;
  if (quality.num_faces < min_faces)
    Fail("the mesh is broken: {} faces from {} points (at least {:.0f} expected)",
         quality.num_faces, quality.num_points, std::ceil(min_faces));
  const double max_distance =
      std::max(limits.max_relative_distance * quality.extent, quality.spacing);
  if (quality.median_distance > max_distance)
    Fail(
        "the mesh is broken: its vertices lie a median {:.4g} from the points, {:.2f} % of the "
        "cloud's extent {:.4g} (at most {:.4g} expected: {:.2f} % of the extent or the point "
        "spacing {:.4g})",
        quality.median_distance, 100 * quality.RelativeDistance(), quality.extent, max_distance,
        100 * limits.max_relative_distance, quality.spacing);
}

}  // namespace varsfm
