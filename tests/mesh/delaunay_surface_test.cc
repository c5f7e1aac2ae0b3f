// The visibility surface on point sets with a known surface and known cameras.
#include "varsfm/mesh/delaunay_surface.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <Eigen/Geometry>

#include "support/test_data.h"
#include "varsfm/io/colmap_model.h"
#include "varsfm/io/ply.h"
#include "varsfm/io/point_visibility.h"
#include "varsfm/mesh/mesh_topology.h"
#include "varsfm/mesh/nearest_points.h"
#include "varsfm/mesh/point_grid.h"
#include "varsfm/mesh/surface.h"
#include "varsfm/mesh/surface_input.h"
#include "varsfm/scene/holdout.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

// n points evenly on the unit sphere (Fibonacci lattice) with z >= min_z, each seen by the
// viewpoints (at distance 4 along the six axes, or only +z when top_only) in front of it. With
// `noise`, radii vary by up to that much (deterministic), as dense points do; without, all
// points are cospherical, a degenerate Delaunay input.
PointCloud SeenSphere(int n, double min_z, bool top_only, double noise = 0) {
  PointCloud cloud;
  cloud.viewpoints = {{0, 0, 4}};
  if (!top_only)
    cloud.viewpoints.insert(cloud.viewpoints.end(),
                            {{0, 0, -4}, {4, 0, 0}, {-4, 0, 0}, {0, 4, 0}, {0, -4, 0}});
  const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1 - 2 * (i + 0.5) / n;
    const double r = std::sqrt(1 - z * z);
    const double radius = 1 + noise * std::sin(12.9898 * i);
    const Eigen::Vector3d p =
        radius * Eigen::Vector3d(r * std::cos(golden * i), r * std::sin(golden * i), z);
    if (z < min_z) continue;
    std::vector<uint32_t> views;
    for (uint32_t v = 0; v < cloud.viewpoints.size(); ++v)
      if (p.dot(cloud.viewpoints[v] - p) > 0.1) views.push_back(v);
    if (views.empty()) continue;
    cloud.points.push_back(p);
    cloud.visibility.push_back(views);
  }
  return cloud;
}

double SignedVolume(const TriangleMesh& mesh) {
  double volume = 0;
  for (const auto& f : mesh.faces)
    volume += mesh.vertices[f[0]].dot(mesh.vertices[f[1]].cross(mesh.vertices[f[2]])) / 6;
  return volume;
}

TEST(DelaunaySurface, SphereSeenFromAllSidesIsClosedAndOutward) {
  const PointCloud cloud = SeenSphere(6000, -2, false);
  const double spacing = AverageNearestSpacing(cloud.points);
  DelaunaySurfaceOptions options;
  options.merge_spacing = 0.01;      // keep every point
  options.smoothing_iterations = 0;  // and leave them: the vertices are then the data
  DelaunaySurfaceStats stats;
  const TriangleMesh mesh = ReconstructDelaunaySurface(cloud, spacing, options, &stats);
  EXPECT_EQ(stats.merged_points, cloud.points.size());
  EXPECT_GT(stats.rays, cloud.points.size());
  for (const auto& v : mesh.vertices) ASSERT_NEAR(v.norm(), 1.0, 1e-12);
  EXPECT_GT(mesh.vertices.size(), 0.99 * cloud.points.size());
  const EdgeTopology topology = ComputeEdgeTopology(mesh);
  EXPECT_EQ(topology.boundary_edges, 0u);
  EXPECT_LT(topology.non_manifold_edges, topology.num_edges / 1000);
  // Counter-clockwise seen from outside: the signed volume is the ball's (a polyhedron
  // inscribed in it, slightly less).
  EXPECT_NEAR(SignedVolume(mesh), 4.0 / 3 * std::numbers::pi, 0.02 * 4.0 / 3 * std::numbers::pi);
}

TEST(DelaunaySurface, AtMostTheMergedPointsAskedForAndStillTheSurface) {
  const PointCloud cloud = SeenSphere(20000, -2, false, 0.002);
  const double spacing = AverageNearestSpacing(cloud.points);
  DelaunaySurfaceOptions options;
  DelaunaySurfaceStats uncapped_stats, capped;
  const TriangleMesh uncapped =
      ReconstructDelaunaySurface(cloud, spacing, options, &uncapped_stats);
  ASSERT_GT(uncapped_stats.merged_points, 4000u);
  EXPECT_DOUBLE_EQ(uncapped_stats.merge_voxel, options.merge_spacing * spacing);
  // A cap above what merge_spacing leaves changes nothing.
  options.max_merged_points = uncapped_stats.merged_points;
  const TriangleMesh same = ReconstructDelaunaySurface(cloud, spacing, options);
  EXPECT_EQ(same.vertices, uncapped.vertices);
  EXPECT_EQ(same.faces, uncapped.faces);
  // Below it the points merge in a larger voxel, and the surface is the same sphere.
  options.max_merged_points = 1500;
  const TriangleMesh mesh = ReconstructDelaunaySurface(cloud, spacing, options, &capped);
  EXPECT_LE(capped.merged_points, 1500u);
  EXPECT_GT(capped.merged_points, 750u);  // the voxel grows by about what the cap asks
  EXPECT_GT(capped.merge_voxel, options.merge_spacing * spacing);
  const EdgeTopology topology = ComputeEdgeTopology(mesh);
  EXPECT_LT(topology.boundary_edges, topology.num_edges / 100);
  EXPECT_NEAR(SignedVolume(mesh), 4.0 / 3 * std::numbers::pi, 0.05 * 4.0 / 3 * std::numbers::pi);
}

TEST(DelaunaySurface, OpenCapSeenFromAboveDoesNotCloseOverTheOpenSide) {
  // A cap (z >= 0.3) seen only from above: the surface must stay on the cap; nothing may span
  // the open side (screened Poisson would close it with a balloon the trim must cut away).
  const PointCloud cloud = SeenSphere(20000, 0.3, true, 0.002);
  const double spacing = AverageNearestSpacing(cloud.points);
  const TriangleMesh mesh = ReconstructDelaunaySurface(cloud, spacing, {});
  ASSERT_GT(mesh.faces.size(), cloud.points.size() / 4);
  size_t facing_away = 0;
  for (const auto& f : mesh.faces) {
    const Eigen::Vector3d centroid =
        (mesh.vertices[f[0]] + mesh.vertices[f[1]] + mesh.vertices[f[2]]) / 3;
    ASSERT_NEAR(centroid.norm(), 1.0, 3 * spacing);
    // Outward like the sphere, facing the camera; only thin faces along the rim, where the
    // inside volume meets the convex hull's flat bottom, face away.
    const Eigen::Vector3d normal = (mesh.vertices[f[1]] - mesh.vertices[f[0]])
                                       .cross(mesh.vertices[f[2]] - mesh.vertices[f[0]]);
    facing_away += normal.dot(centroid) < 0;
  }
  EXPECT_LT(facing_away, mesh.faces.size() / 10);
  EXPECT_GT(ComputeEdgeTopology(mesh).boundary_edges, 0u);  // open
}

TEST(DelaunaySurface, SameBitsOnOneAndTwoThreads) {
  // Noisy radii (no cospherical degeneracy) and three gaps in the points, which the cut bridges
  // with long faces; those are cut and the holes they leave filled.
  PointCloud cloud = SeenSphere(8000, -2, false, 0.01);
  PointCloud gappy = cloud;
  gappy.points.clear();
  gappy.visibility.clear();
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    const Eigen::Vector3d u = cloud.points[i].normalized();
    if (u.dot(Eigen::Vector3d(1, 1, 1).normalized()) > 0.99 ||
        u.dot(Eigen::Vector3d(-1, 0.5, 0.2).normalized()) > 0.99 ||
        u.dot(Eigen::Vector3d(0.3, -1, -0.4).normalized()) > 0.99)
      continue;
    gappy.points.push_back(cloud.points[i]);
    gappy.visibility.push_back(cloud.visibility[i]);
  }
  cloud = gappy;
  const double spacing = AverageNearestSpacing(cloud.points);
  DelaunaySurfaceOptions options;
  options.long_faces.max_edge_factor = 2;
  options.hole_filling.max_edges = 100;
  TriangleMesh meshes[2];
  DelaunaySurfaceStats stats[2];
  for (int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    meshes[threads - 1] = ReconstructDelaunaySurface(cloud, spacing, options, &stats[threads - 1]);
  }
  EXPECT_GT(stats[0].long_faces.long_faces, 0u);
  EXPECT_GT(stats[0].holes.filled_loops, 0u);
  EXPECT_EQ(stats[0].holes.added_faces, stats[1].holes.added_faces);
  EXPECT_EQ(meshes[0].faces, meshes[1].faces);
  EXPECT_EQ(meshes[0].vertices, meshes[1].vertices);
}

TEST(DelaunaySurface, DeterministicAndThroughTheSurfaceStage) {
  PointCloud cloud = SeenSphere(3000, -0.5, false);
  cloud.colors.assign(cloud.points.size(), {10, 20, 30});
  SurfaceOptions options;
  options.method = SurfaceMethod::kDelaunay;
  SurfaceStats stats;
  const TriangleMesh a = ReconstructSurface(cloud, options, &stats);
  const TriangleMesh b = ReconstructSurface(cloud, options);
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.faces, b.faces);
  ASSERT_EQ(a.colors.size(), a.vertices.size());
  EXPECT_EQ(a.colors[0], (Eigen::Matrix<uint8_t, 3, 1>(10, 20, 30)));
  EXPECT_EQ(stats.quality.num_faces, a.faces.size());
  EXPECT_GT(stats.delaunay.cells, stats.delaunay.merged_points);
  // Without visibility: one line naming what is missing.
  cloud.visibility.clear();
  try {
    ReconstructSurface(cloud, options);
    ADD_FAILURE() << "no error without visibility";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("visibility"), std::string::npos) << e.what();
  }
  EXPECT_EQ(ParseSurfaceMethod("delaunay"), SurfaceMethod::kDelaunay);
  options.delaunay.merge_spacing = 0;
  EXPECT_THROW(options.Check(), Error);
}

TEST(DelaunaySurface, AMeshAsCoarseAsTheCapAskedIsNoBrokenMesh) {
  // The mesh check asks for a face per 50 points (mesh_quality.h) of the surface at the asked
  // merge spacing; a cap that merges more coarsely lowers that with the square of the voxel.
  const PointCloud cloud = SeenSphere(20000, -2, false, 0.002);
  SurfaceOptions options;
  options.method = SurfaceMethod::kDelaunay;
  options.delaunay.max_merged_points = 150;
  SurfaceStats stats;
  const TriangleMesh mesh = ReconstructSurface(cloud, options, &stats);
  EXPECT_LE(stats.delaunay.merged_points, 150u);
  EXPECT_LT(mesh.faces.size(), cloud.points.size() / 50);  // below the check's uncapped limit
  EXPECT_GT(mesh.faces.size(), 150u);
}

// PatchMatch's points carry no cameras in the PLY: their visibility is dense.ply.vis (image ids)
// and the camera centres are the sparse model's. Read that way, the cloud is the one that
// carries its own visibility, and so is its surface.
TEST(DelaunaySurface, VisibilityBesideThePlyWithTheModelsCameras) {
  testing::TempDir dir("delaunay_vis");
  const PointCloud seen = SeenSphere(3000, -0.5, false);
  // One image per viewpoint, with ids 3, 5, 7, ... so ids and indices differ; an unregistered
  // image with no points, which must not become a viewpoint.
  Reconstruction model;
  Camera camera = Camera::FromFocal(640, 480, 500);
  camera.camera_id = 1;
  model.AddCamera(camera);
  PointVisibility ids(seen.points.size());
  for (size_t p = 0; p < seen.points.size(); ++p)
    for (uint32_t v : seen.visibility[p]) ids[p].push_back(3 + 2 * v);
  for (uint32_t v = 0; v <= seen.viewpoints.size(); ++v) {
    Image image;
    image.image_id = 3 + 2 * v;
    image.name = "view" + std::to_string(v) + ".jpg";
    image.camera_id = camera.camera_id;
    const Eigen::Matrix3d rotation =
        Eigen::AngleAxisd(0.3 * v, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    const Eigen::Vector3d centre =
        v < seen.viewpoints.size() ? seen.viewpoints[v] : Eigen::Vector3d(9, 9, 9);
    image.cam_from_world = Rigid3d(rotation, -(rotation * centre));
    image.registered = v < seen.viewpoints.size();
    model.AddImage(image);
  }
  WriteColmapModel(model, dir.path() / "sparse" / "0", {.binary = true});
  PointCloud bare = seen;
  bare.visibility.clear();
  bare.viewpoints.clear();
  const auto ply = dir.path() / "dense.ply";
  WritePly(ply, bare);
  // Without dense.ply.vis: one line naming the file and what is missing.
  try {
    ReadSurfaceInput(ply, SurfaceMethod::kDelaunay);
    ADD_FAILURE() << "no error without dense.ply.vis";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("dense.ply.vis"), std::string::npos) << e.what();
  }
  WritePointVisibility(dir.path() / "dense.ply.vis", ids);

  const SurfaceInput input = ReadSurfaceInput(ply, SurfaceMethod::kDelaunay);  // OUT/sparse
  const PointCloud& read = input.cloud;
  EXPECT_EQ(input.views.size(), model.NumRegisteredImages());
  ASSERT_EQ(read.viewpoints.size(), seen.viewpoints.size());
  for (size_t v = 0; v < seen.viewpoints.size(); ++v)
    EXPECT_LT((read.viewpoints[v] - seen.viewpoints[v]).norm(), 1e-9);
  EXPECT_EQ(read.visibility, seen.visibility);
  PointCloud written = seen;
  written.points = read.points;  // as the PLY stores them
  const double spacing = AverageNearestSpacing(read.points);
  const TriangleMesh a = ReconstructDelaunaySurface(read, spacing, {});
  const TriangleMesh b = ReconstructDelaunaySurface(written, spacing, {});
  EXPECT_EQ(a.faces, b.faces);
  EXPECT_GT(a.faces.size(), 1000u);
  // A model folder given explicitly, and the one-line errors of a mismatched pair.
  EXPECT_EQ(ReadSurfaceInput(ply, SurfaceMethod::kDelaunay, dir.path() / "sparse" / "0")
                .cloud.visibility.size(),
            seen.points.size());
  // The held-out views (every N-th registered image by name, as densify and texture leave them
  // out) do not judge the long faces.
  const SurfaceInput held = ReadSurfaceInput(ply, SurfaceMethod::kDelaunay, {}, 2);
  const std::vector<image_t> held_out = HeldOutImageIds(model, 2);
  ASSERT_FALSE(held_out.empty());
  EXPECT_EQ(held.views.size() + held_out.size(), model.NumRegisteredImages());
  for (const PosedCamera& view : held.views)
    for (const image_t id : held_out)
      EXPECT_GT((view.cam_from_world.Center() - model.image(id).cam_from_world.Center()).norm(),
                1e-9);
  EXPECT_EQ(held.cloud.visibility, seen.visibility);
  // A cloud of more points than asked for is read merged: the whole cloud merged at that voxel,
  // its image ids turned into the same viewpoints.
  const SurfaceInput merged =
      ReadSurfaceInput(ply, SurfaceMethod::kDelaunay, {}, 0, seen.points.size() / 4);
  EXPECT_EQ(merged.file_points, seen.points.size());
  ASSERT_GT(merged.read_voxel, 0);
  EXPECT_LE(merged.cloud.points.size(), seen.points.size() / 4);
  const PointCloud expected = VoxelDownsample(input.cloud, merged.read_voxel);
  EXPECT_EQ(merged.cloud.points, expected.points);
  EXPECT_EQ(merged.cloud.visibility, expected.visibility);
  EXPECT_EQ(merged.cloud.viewpoints, input.cloud.viewpoints);
  PointCloud other = bare;
  ids[0].push_back(99);  // no such image
  EXPECT_THROW(AttachVisibility(ids, model, &other), Error);
  ids[0].pop_back();
  ids[0].push_back(3 + 2 * static_cast<image_t>(seen.viewpoints.size()));  // not registered
  EXPECT_THROW(AttachVisibility(ids, model, &other), Error);
  ids.pop_back();
  EXPECT_THROW(AttachVisibility(ids, model, &other), Error);
  WritePointVisibility(dir.path() / "dense.ply.vis", ids);
  try {
    ReadSurfaceInput(ply, SurfaceMethod::kDelaunay);
    ADD_FAILURE() << "no error for a .vis of another cloud";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("dense.ply.vis"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace varsfm
