#include "varsfm/mesh/screened_poisson.h"

#include <open3d/geometry/PointCloud.h>
#include <open3d/geometry/TriangleMesh.h>
#include <open3d/utility/Logging.h>

#include "varsfm/util/error.h"

namespace varsfm {

ScreenedPoissonSurface ReconstructScreenedPoisson(const PointCloud& cloud, int depth,
                                                  int num_threads) {
  if (!cloud.HasNormals()) Fail("screened Poisson reconstruction needs point normals");
  if (depth < 1 || num_threads < 1) Fail("screened Poisson: depth and threads must be >= 1");
  // Open3D prints its progress at debug level only; keep it from writing to stdout otherwise.
  open3d::utility::SetVerbosityLevel(open3d::utility::VerbosityLevel::Error);
  open3d::geometry::PointCloud oriented;
  oriented.points_ = cloud.points;
  oriented.normals_ = cloud.normals;
  // width 0: depth decides; scale 1.1: the octree cube is 10 % larger than the points' bounding
  // cube (Kazhdan's default), so the surface is not clipped at the border; linear_fit off: the
  // iso-vertices come from the marching-cubes interpolation of the paper.
  auto [surface, densities] = open3d::geometry::TriangleMesh::CreateFromPointCloudPoisson(
      oriented, static_cast<size_t>(depth), /*width=*/0.0f, /*scale=*/1.1f,
      /*linear_fit=*/false, num_threads);
  if (!surface || surface->triangles_.empty()) Fail("screened Poisson reconstruction failed");
  ScreenedPoissonSurface out;
  out.mesh.vertices = std::move(surface->vertices_);
  out.mesh.faces.reserve(surface->triangles_.size());
  for (const Eigen::Vector3i& f : surface->triangles_) out.mesh.faces.push_back(f);
  out.densities = std::move(densities);
  return out;
}

}  // namespace varsfm
