#include "varsfm/mesh/surface.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <utility>

#include <CGAL/Advancing_front_surface_reconstruction.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Random.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/poisson_surface_reconstruction.h>
#include <CGAL/property_map.h>

#include "varsfm/mesh/point_grid.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"

namespace varsfm {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalPoint = Kernel::Point_3;
using CgalVector = Kernel::Vector_3;
using CgalMesh = CGAL::Surface_mesh<CgalPoint>;

CgalPoint ToCgal(const Eigen::Vector3d& p) { return {p.x(), p.y(), p.z()}; }

// Downsamples with a growing voxel until at most max_points remain. Points sample surfaces, so
// the count falls about as the square of the voxel size: each step jumps by that estimate
// (at least 1.1x) rather than by a fixed factor, which took ~6 passes over a million points.
PointCloud LimitPoints(const PointCloud& cloud, size_t max_points) {
  if (cloud.points.size() <= max_points) return cloud;
  double voxel = AverageNearestSpacing(cloud.points);
  PointCloud reduced = VoxelDownsample(cloud, voxel);
  while (reduced.points.size() > max_points) {
    const double ratio = static_cast<double>(reduced.points.size()) / max_points;
    voxel *= std::max(1.1, 1.02 * std::sqrt(ratio));
    reduced = VoxelDownsample(cloud, voxel);
  }
  return reduced;
}

TriangleMesh Poisson(const PointCloud& cloud, double spacing, const SurfaceOptions& options) {
  std::vector<std::pair<CgalPoint, CgalVector>> oriented;
  oriented.reserve(cloud.points.size());
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    const Eigen::Vector3d& n = cloud.normals[i];
    oriented.emplace_back(ToCgal(cloud.points[i]), CgalVector(n.x(), n.y(), n.z()));
  }
  CgalMesh surface;
  using Pair = std::pair<CgalPoint, CgalVector>;
  // CGAL's surface mesher starts from random points drawn from CGAL::get_default_random(),
  // a thread-local generator seeded with the time of day: reseed it, so the mesh no longer
  // changes from run to run (it did, by ~1 % of the faces on fountain-P11). Known remainder:
  // the mesher also orders work by handle addresses, and its large blocks are mmap'ed at
  // addresses that address-space randomisation changes per run, so a run can still differ by
  // a few tenths of a percent of the faces.
  CGAL::get_default_random() = CGAL::Random(0);
  const bool ok = CGAL::poisson_surface_reconstruction_delaunay(
      oriented.begin(), oriented.end(), CGAL::First_of_pair_property_map<Pair>(),
      CGAL::Second_of_pair_property_map<Pair>(), surface, spacing, /*sm_angle=*/20.0,
      /*sm_radius=*/30.0, options.approximation_distance);
  if (!ok || surface.number_of_faces() == 0) Fail("Poisson surface reconstruction failed");

  TriangleMesh mesh;
  std::vector<int> index(surface.number_of_vertices(), -1);
  for (CgalMesh::Vertex_index v : surface.vertices()) {
    index[v.idx()] = static_cast<int>(mesh.vertices.size());
    const CgalPoint& p = surface.point(v);
    mesh.vertices.emplace_back(p.x(), p.y(), p.z());
  }
  for (CgalMesh::Face_index f : surface.faces()) {
    Eigen::Vector3i face;
    int k = 0;
    for (CgalMesh::Vertex_index v : CGAL::vertices_around_face(surface.halfedge(f), surface)) {
      if (k < 3) face[k] = index[v.idx()];
      ++k;
    }
    if (k == 3) mesh.faces.push_back(face);
  }
  return mesh;
}

TriangleMesh AdvancingFront(const PointCloud& cloud) {
  std::vector<CgalPoint> points;
  points.reserve(cloud.points.size());
  for (const auto& p : cloud.points) points.push_back(ToCgal(p));
  std::vector<std::array<std::size_t, 3>> facets;
  CGAL::advancing_front_surface_reconstruction(points.begin(), points.end(),
                                               std::back_inserter(facets));
  if (facets.empty()) Fail("advancing-front surface reconstruction produced no faces");
  TriangleMesh mesh;
  mesh.vertices = cloud.points;
  for (const auto& f : facets) {
    mesh.faces.emplace_back(static_cast<int>(f[0]), static_cast<int>(f[1]), static_cast<int>(f[2]));
  }
  // Orient faces like the input normals (advancing front orients consistently, but its global
  // sign is arbitrary).
  if (cloud.HasNormals()) {
    double agreement = 0;
    for (const Eigen::Vector3i& f : mesh.faces) {
      const Eigen::Vector3d n = (mesh.vertices[f[1]] - mesh.vertices[f[0]])
                                    .cross(mesh.vertices[f[2]] - mesh.vertices[f[0]]);
      agreement += n.dot(cloud.normals[f[0]] + cloud.normals[f[1]] + cloud.normals[f[2]]);
    }
    if (agreement < 0) {
      for (Eigen::Vector3i& f : mesh.faces) std::swap(f[1], f[2]);
    }
  }
  RemoveUnreferencedVertices(&mesh);
  return mesh;
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

PointCloud ReadSurfaceInput(const std::filesystem::path& file, SurfaceMethod method) {
  if (!std::filesystem::is_regular_file(file)) Fail("{}: no such point cloud", file.string());
  PointCloud cloud = ReadPly(file);
  if (cloud.points.empty()) Fail("{}: the point cloud is empty", file.string());
  if (method == SurfaceMethod::kPoisson && !cloud.HasNormals()) {
    Fail("{}: Poisson reconstruction needs normals (nx ny nz); try --method afront", file.string());
  }
  return cloud;
}

SurfaceMethod ParseSurfaceMethod(const std::string& name) {
  if (name == "poisson") return SurfaceMethod::kPoisson;
  if (name == "afront") return SurfaceMethod::kAdvancingFront;
  Fail("unknown surface method '{}' (poisson | afront)", name);
}

TriangleMesh ReconstructSurface(const PointCloud& cloud, const SurfaceOptions& options,
                                SurfaceStats* stats) {
  if (cloud.points.size() < 10) {
    Fail("{} points are too few for a surface (need at least 10)", cloud.points.size());
  }
  const bool poisson = options.method == SurfaceMethod::kPoisson;
  if (poisson && !cloud.HasNormals()) Fail("Poisson reconstruction needs point normals");
  const PointCloud used = LimitPoints(cloud, options.max_points);
  const double spacing = AverageNearestSpacing(used.points);
  spdlog::info("surface: {} of {} points, average spacing {:.4g}", used.points.size(),
               cloud.points.size(), spacing);

  TriangleMesh mesh = poisson ? Poisson(used, spacing, options) : AdvancingFront(used);
  if (stats) {
    stats->input_points = cloud.points.size();
    stats->used_points = used.points.size();
    stats->average_spacing = spacing;
    stats->faces_before_trim = mesh.faces.size();
  }
  const bool trim = poisson && options.trim_factor > 0;
  const double reach = (trim ? options.trim_factor : 3.0) * spacing;
  TrimAndColour(cloud, reach, trim, &mesh);
  if (mesh.faces.empty()) Fail("surface reconstruction left no faces after trimming");
  return mesh;
}

}  // namespace varsfm
