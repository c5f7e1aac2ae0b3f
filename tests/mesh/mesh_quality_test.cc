// The mesh check: a mesh on its points passes, one moved off them or one far too coarse for
// them fails with one line naming the figures; the extent ignores a few far outliers.
#include "varsfm/mesh/mesh_quality.h"

#include <string>

#include <gtest/gtest.h>

#include "varsfm/util/error.h"
#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

// The tests' points are far denser than the check's distance limit; this spacing keeps the
// limit at its fraction of the extent.
constexpr double kSpacing = 1e-4;

// An n x n grid of points on the unit square in z = 0 and a mesh of it: its points as vertices
// (offset by `lift` in z) and two triangles per grid cell.
struct Grid {
  std::vector<Eigen::Vector3d> points;
  TriangleMesh mesh;
};

Grid MakeGrid(int n, double lift) {
  Grid grid;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) grid.points.emplace_back(i / (n - 1.0), j / (n - 1.0), 0.0);
  for (const Eigen::Vector3d& p : grid.points)
    grid.mesh.vertices.push_back(p + lift * Eigen::Vector3d::UnitZ());
  for (int i = 0; i + 1 < n; ++i)
    for (int j = 0; j + 1 < n; ++j) {
      const int a = i * n + j, b = a + 1, c = a + n, d = c + 1;
      grid.mesh.faces.emplace_back(a, c, b);
      grid.mesh.faces.emplace_back(b, c, d);
    }
  return grid;
}

std::string CheckMessage(const MeshQuality& quality) {
  try {
    CheckMeshQuality(quality);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(MeshQuality, RobustExtentIgnoresFarOutliers) {
  Grid grid = MakeGrid(101, 0);
  // 5 % quantiles of a uniform grid over [0, 1]^2: the box is 0.9 x 0.9, diagonal 0.9 sqrt 2.
  EXPECT_NEAR(RobustExtent(grid.points), 0.9 * std::sqrt(2.0), 0.01);
  for (int k = 0; k < 100; ++k) grid.points.emplace_back(1000, -1000, 1000);  // < 1 %
  EXPECT_NEAR(RobustExtent(grid.points), 0.9 * std::sqrt(2.0), 0.03);
}

TEST(MeshQuality, AMeshOnItsPointsPasses) {
  const Grid grid = MakeGrid(60, 0);
  const MeshQuality quality = MeasureMeshQuality(grid.mesh, NearestPoints(grid.points), kSpacing);
  EXPECT_EQ(quality.num_faces, 2u * 59 * 59);
  EXPECT_EQ(quality.median_distance, 0);
  EXPECT_EQ(CheckMessage(quality), "");
}

TEST(MeshQuality, AMeshOffItsPointsFailsNamingTheDistance) {
  // Lifted by 1 % of the unit square: the median distance is 0.01, above 0.5 % of the extent.
  const Grid grid = MakeGrid(60, 0.01);
  const MeshQuality quality = MeasureMeshQuality(grid.mesh, NearestPoints(grid.points), kSpacing);
  EXPECT_NEAR(quality.median_distance, 0.01, 1e-12);
  const std::string message = CheckMessage(quality);
  EXPECT_NE(message.find("median 0.01 from the points"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  // Lifted by 0.1 %: within the limit.
  const Grid close = MakeGrid(60, 0.001);
  EXPECT_EQ(CheckMessage(MeasureMeshQuality(close.mesh, NearestPoints(close.points), kSpacing)),
            "");
  // A cloud too sparse for 0.5 % of its extent is held to its spacing instead.
  EXPECT_EQ(CheckMessage(MeasureMeshQuality(grid.mesh, NearestPoints(grid.points), 0.02)), "");
}

TEST(MeshQuality, ATinyMeshFailsNamingItsSize) {
  // Two triangles over 3600 points: a collapsed surface.
  const Grid dense = MakeGrid(60, 0);
  const Grid coarse = MakeGrid(2, 0);
  const MeshQuality quality =
      MeasureMeshQuality(coarse.mesh, NearestPoints(dense.points), kSpacing);
  const std::string message = CheckMessage(quality);
  EXPECT_NE(message.find("2 faces from 3600 points"), std::string::npos) << message;
}

TEST(MeshQuality, LimitsAreChecked) {
  MeshQualityLimits limits;
  EXPECT_NO_THROW(limits.Check());
  limits.max_relative_distance = 0;
  EXPECT_THROW(limits.Check(), OptionError);
}

}  // namespace
}  // namespace varsfm
