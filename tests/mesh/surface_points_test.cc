// What every surface method's input passes first (surface_points.h): clouds that crashed
// screened Poisson or hung the advancing front's downsampling and the Delaunay surface's ray
// walks now give one line, or, for a few far outliers, the surface of the rest.
#include "varsfm/mesh/surface_points.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "varsfm/mesh/surface.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

// n points on the unit sphere (Fibonacci lattice) with radii varying by 1 % (as dense points
// do), outward normals, a colour, and visibility from viewpoints at distance 4 along the six
// axes in front of each point: input for every method.
PointCloud SeenSphere(int n) {
  PointCloud cloud;
  cloud.viewpoints = {{0, 0, 4}, {0, 0, -4}, {4, 0, 0}, {-4, 0, 0}, {0, 4, 0}, {0, -4, 0}};
  const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1 - 2 * (i + 0.5) / n;
    const double r = std::sqrt(1 - z * z);
    const Eigen::Vector3d unit(r * std::cos(golden * i), r * std::sin(golden * i), z);
    const Eigen::Vector3d p = (1 + 0.01 * std::sin(12.9898 * i)) * unit;
    std::vector<uint32_t> views;
    for (uint32_t v = 0; v < cloud.viewpoints.size(); ++v)
      if (p.dot(cloud.viewpoints[v] - p) > 0.1) views.push_back(v);
    cloud.points.push_back(p);
    cloud.normals.push_back(unit);
    cloud.colors.emplace_back(200, 100, 50);
    cloud.visibility.push_back(views);
  }
  return cloud;
}

// `cloud` with `count` more points at x = `x` (seen from the first viewpoint).
PointCloud WithPointsAt(PointCloud cloud, size_t count, double x) {
  for (size_t i = 0; i < count; ++i) {
    cloud.points.emplace_back(x, 0.01 * static_cast<double>(i), 0.5);
    cloud.normals.emplace_back(1, 0, 0);
    cloud.colors.emplace_back(0, 0, 0);
    cloud.visibility.push_back({0});
  }
  return cloud;
}

// The faces, each rotated to start at its least index, sorted: the advancing front (CGAL) lists
// the same faces in an order that can change between calls in one process.
std::vector<std::array<int, 3>> SortedFaces(const TriangleMesh& mesh) {
  std::vector<std::array<int, 3>> faces;
  for (const Eigen::Vector3i& f : mesh.faces) {
    int k = 0;
    for (int j = 1; j < 3; ++j)
      if (f[j] < f[k]) k = j;
    faces.push_back({f[k], f[(k + 1) % 3], f[(k + 2) % 3]});
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

SurfaceOptions Method(SurfaceMethod method) {
  SurfaceOptions options;
  options.method = method;
  return options;
}

constexpr SurfaceMethod kMethods[] = {SurfaceMethod::kDelaunay, SurfaceMethod::kScreenedPoisson,
                                      SurfaceMethod::kAdvancingFront};

// ReconstructSurface(cloud) with every method throws one line holding `words`.
void ExpectRefusedByEveryMethod(const PointCloud& cloud, const std::string& words) {
  for (const SurfaceMethod method : kMethods) {
    try {
      ReconstructSurface(cloud, Method(method));
      ADD_FAILURE() << "no error from method " << static_cast<int>(method);
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(words), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  }
}

TEST(SurfacePoints, RobustBoundsIgnoreAFewFarPoints) {
  const PointCloud cloud = WithPointsAt(SeenSphere(2000), 5, 1e30);
  const RobustBounds bounds = MeasureRobustBounds(cloud.points);
  EXPECT_LT(bounds.centre.norm(), 0.05);
  // The 5th-95th percentile box of a unit sphere: 0.9 x 2 per axis, sqrt(3) x that across.
  EXPECT_NEAR(bounds.extent, std::sqrt(3.0) * 1.8, 0.05);
}

TEST(SurfacePoints, IdenticalPointsAreRefusedByEveryMethod) {
  // 500 copies of one point crashed screened Poisson (a zero spacing, hence a NaN depth).
  PointCloud same = WithPointsAt({}, 500, 1.0);
  for (Eigen::Vector3d& p : same.points) p = Eigen::Vector3d(1, 2, 3);
  same.viewpoints = {{0, 0, 10}};
  ExpectRefusedByEveryMethod(same, "no spatial extent");
  // Copies a float step apart are one point to a float PLY and to Open3D's octree alike.
  PointCloud nearly = same;
  for (size_t i = 0; i < nearly.points.size(); ++i)
    nearly.points[i].x() += 1e-9 * std::sin(static_cast<double>(i));
  ExpectRefusedByEveryMethod(nearly, "no spatial extent");
}

TEST(SurfacePoints, AdvancingFrontOnManyIdenticalPointsEnds) {
  // Over max_points the downsampling grew a voxel of size zero forever.
  PointCloud same = WithPointsAt({}, 70000, 1.0);
  SurfaceOptions options = Method(SurfaceMethod::kAdvancingFront);
  EXPECT_THROW(ReconstructSurface(same, options), Error);
}

TEST(SurfacePoints, EveryPointTwinnedHasNoSpacing) {
  PointCloud twinned = SeenSphere(1000);
  const PointCloud once = twinned;
  for (const Eigen::Vector3d& p : once.points) twinned.points.push_back(p);
  twinned.normals.insert(twinned.normals.end(), once.normals.begin(), once.normals.end());
  twinned.colors.insert(twinned.colors.end(), once.colors.begin(), once.colors.end());
  twinned.visibility.insert(twinned.visibility.end(), once.visibility.begin(),
                            once.visibility.end());
  ExpectRefusedByEveryMethod(twinned, "no spacing");
}

TEST(SurfacePoints, WithoutFarPointsKeepsEveryAttributeInStep) {
  const PointCloud clean = SeenSphere(1000);
  EXPECT_FALSE(WithoutFarPoints(clean, MeasureRobustBounds(clean.points)).has_value());
  // Within 100 extents (~3 units each) a point stays; beyond, it goes.
  const PointCloud mixed = WithPointsAt(WithPointsAt(clean, 2, 250.0), 3, 1e6);
  const std::optional<PointCloud> near = WithoutFarPoints(mixed, MeasureRobustBounds(mixed.points));
  ASSERT_TRUE(near.has_value());
  ASSERT_EQ(near->points.size(), clean.points.size() + 2);
  EXPECT_EQ(near->normals.size(), near->points.size());
  EXPECT_EQ(near->colors.size(), near->points.size());
  EXPECT_EQ(near->visibility.size(), near->points.size());
  EXPECT_EQ(near->viewpoints, mixed.viewpoints);
  EXPECT_EQ(near->points.back(), mixed.points[clean.points.size() + 1]);
  EXPECT_EQ(near->visibility[7], mixed.visibility[7]);
}

TEST(SurfacePoints, FarOutliersGiveTheSurfaceOfTheRest) {
  // Ten points at x = 1e30 made each Delaunay ray walk its whole step budget (a hang): they
  // are dropped before anything is built, so every method's mesh is the clean cloud's.
  const PointCloud clean = SeenSphere(3000);
  const PointCloud far = WithPointsAt(clean, 10, 1e30);
  for (const SurfaceMethod method : kMethods) {
    SurfaceStats clean_stats, far_stats;
    const TriangleMesh expected = ReconstructSurface(clean, Method(method), &clean_stats);
    const TriangleMesh mesh = ReconstructSurface(far, Method(method), &far_stats);
    EXPECT_EQ(mesh.vertices, expected.vertices) << static_cast<int>(method);
    EXPECT_EQ(SortedFaces(mesh), SortedFaces(expected)) << static_cast<int>(method);
    EXPECT_EQ(mesh.colors, expected.colors) << static_cast<int>(method);
    EXPECT_EQ(far_stats.input_points, far.points.size());
    EXPECT_EQ(far_stats.quality.num_points, clean.points.size());
  }
}

TEST(SurfacePoints, HalfTheCloudFarAwayIsRefused) {
  // No robust statistic can tell which half is the scene: the spread over the spacing refuses it
  // (the Delaunay surface hung on it).
  const PointCloud clean = SeenSphere(1000);
  PointCloud halves = clean;
  for (size_t i = 0; i < halves.points.size(); i += 2) halves.points[i].x() = 1e30;
  ExpectRefusedByEveryMethod(halves, "spacings across");
}

}  // namespace
}  // namespace varsfm
