// A cloud read merged (merged_read.h) is the cloud read whole and merged at the same voxel, with
// at most the points asked for, the files' visibility merged alike.
#include "varsfm/mesh/merged_read.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "support/test_data.h"
#include "varsfm/io/ply.h"
#include "varsfm/io/point_visibility.h"
#include "varsfm/mesh/point_grid.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

// n points on a wavy 4 x 3 sheet (a surface, as dense points are), normals, colours varying
// with the position, and per point two to four of eight views, unsorted for every fifth point.
PointCloud WavySheet(int n, PointVisibility* ids) {
  PointCloud cloud;
  const int columns = static_cast<int>(std::sqrt(n * 4.0 / 3.0));
  for (int i = 0; i < n; ++i) {
    const double x = 4.0 * (i % columns) / columns + 1e-3 * std::sin(7.1 * i);
    const double y = 3.0 * (i / columns) / (n / columns) + 1e-3 * std::cos(3.3 * i);
    const double z = 0.2 * std::sin(2 * x) * std::cos(3 * y);
    cloud.points.emplace_back(x, y, z);
    cloud.normals.push_back(Eigen::Vector3d(-0.4 * std::cos(2 * x) * std::cos(3 * y),
                                            0.6 * std::sin(2 * x) * std::sin(3 * y), 1)
                                .normalized());
    cloud.colors.emplace_back(static_cast<uint8_t>(60 * x), static_cast<uint8_t>(80 * y), 9);
    std::vector<image_t> seen = {static_cast<image_t>(i % 8), static_cast<image_t>((i + 3) % 8)};
    if (i % 3 == 0) seen.push_back(static_cast<image_t>((i / 7) % 8));
    std::sort(seen.begin(), seen.end());
    seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
    if (i % 5 == 0) std::reverse(seen.begin(), seen.end());
    ids->push_back(seen);
  }
  return cloud;
}

TEST(MergedRead, IsTheWholeCloudMergedAtTheVoxelItChose) {
  testing::TempDir tmp("merged_read");
  PointVisibility ids;
  PointCloud cloud = WavySheet(60000, &ids);
  WritePly(tmp.path() / "dense.ply", cloud);
  WritePointVisibility(tmp.path() / "dense.ply.vis", ids);
  const size_t max_points = 5000;
  const MergedRead read =
      ReadMerged(tmp.path() / "dense.ply", tmp.path() / "dense.ply.vis", max_points);
  EXPECT_EQ(read.file_points, 60000u);
  EXPECT_LE(read.cloud.points.size(), max_points);
  // Not far below: the first voxel comes from the spacing, each growth from the overshoot.
  EXPECT_GT(read.cloud.points.size(), max_points / 3);
  EXPECT_GE(read.passes, 2);
  EXPECT_TRUE(read.cloud.visibility.empty());
  ASSERT_EQ(read.image_ids.size(), read.cloud.points.size());

  // The same as merging the cloud read whole (floats, as in the file) at that voxel.
  PointCloud whole = ReadPly(tmp.path() / "dense.ply");
  whole.visibility.assign(ids.begin(), ids.end());
  const PointCloud expected = VoxelDownsample(whole, read.voxel);
  ASSERT_EQ(expected.points.size(), read.cloud.points.size());
  for (size_t i = 0; i < expected.points.size(); ++i) {
    ASSERT_EQ(expected.points[i], read.cloud.points[i]) << i;
    ASSERT_EQ(expected.normals[i], read.cloud.normals[i]) << i;
    ASSERT_EQ(expected.colors[i], read.cloud.colors[i]) << i;
    ASSERT_EQ(expected.visibility[i], read.image_ids[i]) << i;
    ASSERT_TRUE(std::is_sorted(read.image_ids[i].begin(), read.image_ids[i].end()));
  }
}

TEST(MergedRead, KeepsTheFilesOwnVisibilityAndViewpoints) {
  testing::TempDir tmp("merged_read_own");
  PointVisibility ids;
  PointCloud cloud = WavySheet(20000, &ids);
  cloud.visibility.assign(ids.begin(), ids.end());
  for (auto& views : cloud.visibility) std::sort(views.begin(), views.end());
  for (int v = 0; v < 8; ++v) cloud.viewpoints.emplace_back(v, 0, 5);
  WritePly(tmp.path() / "cloud.ply", cloud);
  const MergedRead read = ReadMerged(tmp.path() / "cloud.ply", {}, 1000);
  EXPECT_LE(read.cloud.points.size(), 1000u);
  EXPECT_EQ(read.cloud.viewpoints, cloud.viewpoints);
  ASSERT_EQ(read.cloud.visibility.size(), read.cloud.points.size());
  EXPECT_TRUE(read.image_ids.empty());
  PointCloud whole = ReadPly(tmp.path() / "cloud.ply");
  EXPECT_EQ(VoxelDownsample(whole, read.voxel).visibility, read.cloud.visibility);
}

TEST(MergedRead, CountsThatDisagreeAreOneError) {
  testing::TempDir tmp("merged_read_counts");
  PointVisibility ids;
  const PointCloud cloud = WavySheet(3000, &ids);
  WritePly(tmp.path() / "dense.ply", cloud);
  ids.pop_back();
  WritePointVisibility(tmp.path() / "dense.ply.vis", ids);
  EXPECT_THROW(ReadMerged(tmp.path() / "dense.ply", tmp.path() / "dense.ply.vis", 100), Error);
  // Fewer points than the eight voxels around the origin always keep: refused, not looped on.
  EXPECT_THROW(ReadMerged(tmp.path() / "dense.ply", {}, kMinMergedReadPoints - 1), Error);
}

}  // namespace
}  // namespace varsfm
