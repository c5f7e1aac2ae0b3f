#include "varsfm/mesh/surface.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "varsfm/mesh/advancing_front.h"
#include "varsfm/mesh/mesh_topology.h"
#include "varsfm/mesh/nearest_points.h"
#include "varsfm/mesh/point_grid.h"
#include "varsfm/mesh/screened_poisson.h"
#include "varsfm/mesh/surface_points.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"
#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

// Downsamples with a growing voxel, from the cloud's spacing, until at most max_points remain.
PointCloud LimitPoints(const PointCloud& cloud, size_t max_points, double spacing) {
  if (cloud.points.size() <= max_points) return cloud;
  return VoxelDownsampleAtMost(cloud, max_points, spacing);
}

// The mesh check's limits. A merge voxel that the Delaunay surface's cap on merged points grew
// (delaunay_surface.h, max_merged_points) resolves the surface coarser by design, so the faces
// expected of the points fall with its square (mesh_quality.h: about 2 N / k^2 faces at k
// spacings).
MeshQualityLimits LimitsForTheMerge(const SurfaceOptions& options, double spacing,
                                    const SurfaceStats& s) {
  MeshQualityLimits limits = options.quality;
  const double asked = options.delaunay.merge_spacing * spacing;
  if (options.method == SurfaceMethod::kDelaunay && s.delaunay.merge_voxel > asked) {
    const double coarsening = s.delaunay.merge_voxel / asked;
    limits.min_faces_per_point /= coarsening * coarsening;
  }
  return limits;
}

// The octree depth whose finest cells over the points' bounding cube (enlarged 1.1x, as the
// reconstruction does) are about cell_spacing x spacing wide, clamped. The octree is refined
// only around the samples, so a cube inflated by a few far outliers costs depth, not memory.
int ChooseDepth(const PointCloud& cloud, double spacing, const SurfaceOptions& options) {
  Eigen::Vector3d lo = cloud.points[0], hi = cloud.points[0];
  for (const Eigen::Vector3d& p : cloud.points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double cube = 1.1 * (hi - lo).maxCoeff();
  const double cells = cube / (options.cell_spacing * spacing);
  const int depth = static_cast<int>(std::lround(std::log2(std::max(cells, 1.0))));
  return std::clamp(depth, options.min_depth, options.max_depth);
}

// Drops the vertices (and their faces) whose sampling density is more than `levels` octree
// levels below `depth`.
void TrimByDensity(const std::vector<double>& densities, double min_density, TriangleMesh* mesh) {
  std::erase_if(mesh->faces, [&](const Eigen::Vector3i& f) {
    return densities[f[0]] < min_density || densities[f[1]] < min_density ||
           densities[f[2]] < min_density;
  });
}

// Removes faces with a vertex farther than max_distance from every input point and colours the
// remaining vertices from their nearest input point.
void TrimAndColour(const PointCloud& cloud, double max_distance, bool trim, TriangleMesh* mesh) {
  PointGrid grid(cloud.points, max_distance);
  std::vector<std::optional<size_t>> nearest(mesh->vertices.size());
  for (size_t i = 0; i < mesh->vertices.size(); ++i) {
    nearest[i] = grid.NearestWithinCell(mesh->vertices[i]);
  }
  if (trim) {
    std::erase_if(mesh->faces, [&](const Eigen::Vector3i& f) {
      return !nearest[f[0]] || !nearest[f[1]] || !nearest[f[2]];
    });
  }
  if (cloud.HasColors()) {
    mesh->colors.assign(mesh->vertices.size(), Eigen::Matrix<uint8_t, 3, 1>(128, 128, 128));
    for (size_t i = 0; i < nearest.size(); ++i) {
      if (nearest[i]) mesh->colors[i] = cloud.colors[*nearest[i]];
    }
  }
  RemoveUnreferencedVertices(mesh);
}

}  // namespace

void SurfaceOptions::Check() const {
  CheckPositive("cell_spacing", cell_spacing);
  CheckInRange("min_depth", min_depth, 1, 16);
  CheckInRange("--max-depth", max_depth, min_depth, 16);
  CheckNonNegative("density_trim_levels", density_trim_levels);
  CheckAtLeast("--threads", num_threads, 1);
  CheckAtLeast("--max-points", max_points, 10u);
  CheckNonNegative("--trim", trim_factor);
  delaunay.Check();
  decimation.Check();
  quality.Check();
}

TriangleMesh ReconstructSurface(const PointCloud& input, const SurfaceOptions& options,
                                SurfaceStats* stats, const std::vector<PosedCamera>& views) {
  if (input.points.size() < 10) {
    Fail("{} points are too few for a surface (need at least 10)", input.points.size());
  }
  const bool poisson = options.method == SurfaceMethod::kScreenedPoisson;
  if (poisson && !input.HasNormals()) Fail("Poisson reconstruction needs point normals");
  SurfaceStats local;
  SurfaceStats& s = stats ? *stats : local;
  s = {};
  s.input_points = input.points.size();
  // surface_points.h: no method gets a cloud with no extent, far outliers or a spread beyond its
  // spacing. A cloud without far points is used as it is.
  const RobustBounds bounds = MeasureRobustBounds(input.points);
  CheckSpatialExtent(bounds, input.points.size());
  const std::optional<PointCloud> near = WithoutFarPoints(input, bounds);
  const PointCloud& cloud = near ? *near : input;
  // The spacing's k-d tree is not kept for the quality check below: held through the
  // reconstruction it raised the chain's peak memory by 6 % on fountain-P11.
  const double cloud_spacing = AverageNearestSpacing(cloud.points);
  CheckPointSpacing(cloud.points, cloud_spacing);

  TriangleMesh mesh;
  double spacing = cloud_spacing;
  if (options.method == SurfaceMethod::kScreenedPoisson) {
    s.used_points = cloud.points.size();
    s.depth = ChooseDepth(cloud, spacing, options);
    spdlog::info("surface: screened Poisson on {} points, average spacing {:.4g}, depth {}",
                 cloud.points.size(), spacing, s.depth);
    ScreenedPoissonSurface surface =
        ReconstructScreenedPoisson(cloud, s.depth, options.num_threads);
    mesh = std::move(surface.mesh);
    s.faces_before_trim = mesh.faces.size();
    if (options.density_trim_levels > 0)
      TrimByDensity(surface.densities, s.depth - options.density_trim_levels, &mesh);
  } else if (options.method == SurfaceMethod::kDelaunay) {
    mesh = ReconstructDelaunaySurface(cloud, spacing, options.delaunay, &s.delaunay, views);
    s.used_points = s.delaunay.merged_points;
    s.faces_before_trim = mesh.faces.size() + s.delaunay.long_faces.long_faces -
                          s.delaunay.long_faces.kept + s.delaunay.removed_faces;
  } else {
    const PointCloud used = LimitPoints(cloud, options.max_points, cloud_spacing);
    if (used.points.size() != cloud.points.size()) spacing = AverageNearestSpacing(used.points);
    s.used_points = used.points.size();
    spdlog::info("surface: {} of {} points, average spacing {:.4g}", used.points.size(),
                 cloud.points.size(), spacing);
    mesh = ReconstructAdvancingFront(used);
    s.faces_before_trim = mesh.faces.size();
  }
  s.average_spacing = spacing;
  const bool trim = poisson && options.trim_factor > 0;
  const double reach = (trim ? options.trim_factor : 3.0) * spacing;
  TrimAndColour(cloud, reach, trim, &mesh);
  if (mesh.faces.empty()) Fail("surface reconstruction left no faces after trimming");
  s.quality = MeasureMeshQuality(mesh, NearestPoints(cloud.points), spacing);
  // The check judges the surface before decimation: whether it is tiny against its points is a
  // question about the reconstruction, and a face budget the user asked for (any below ~2 % of
  // the point count) is no broken mesh. Trimmed first, so the budget is not spent on faces
  // about to go.
  CheckMeshQuality(s.quality, LimitsForTheMerge(options, spacing, s));
  s.decimated_faces = DecimateMesh(options.decimation, &mesh);
  if (s.decimated_faces > 0) {
    // What the collapses reached, even short of the budget (they stop where no edge can go
    // without breaking the surface's topology), is the result.
    if (mesh.faces.empty()) Fail("decimation to {} faces left none", options.decimation.max_faces);
    spdlog::info(
        "surface: decimated to {} faces ({} removed{})", mesh.faces.size(), s.decimated_faces,
        mesh.faces.size() > options.decimation.max_faces
            ? fmt::format("; no edge left to collapse towards {}", options.decimation.max_faces)
            : "");
    TrimAndColour(cloud, reach, /*trim=*/false, &mesh);  // colours the new vertices
    s.quality = MeasureMeshQuality(mesh, NearestPoints(cloud.points), spacing);
  }
  return mesh;
}

}  // namespace varsfm
