#include "varsfm/io/point_cloud_stream.h"

#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "support/test_data.h"
#include "varsfm/io/ply.h"
#include "varsfm/io/point_visibility.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;

std::string Bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(PointCloudStream, WritesWhatWritePlyAndWritePointVisibilityWrite) {
  testing::TempDir tmp("point_cloud_stream");
  PointCloud cloud;
  PointVisibility visibility;
  PointCloudStream stream(tmp.path());
  for (int i = 0; i < 50000; ++i) {  // several MB: the scratch files' buffers fill and flush
    const Eigen::Vector3d p(0.1 * i, -1.0 / (i + 1), 1e3 + i);
    const Eigen::Vector3d n = Eigen::Vector3d(i % 3, 1, -(i % 5)).normalized();
    const Eigen::Matrix<uint8_t, 3, 1> c(i % 256, (3 * i) % 256, 7);
    std::vector<image_t> seen_by;
    for (int k = 0; k < i % 6; ++k) seen_by.push_back(static_cast<image_t>(2 * k + i % 2));
    stream.Add(p, n, c, seen_by);
    cloud.points.push_back(p);
    cloud.normals.push_back(n);
    cloud.colors.push_back(c);
    visibility.push_back(seen_by);
  }
  EXPECT_EQ(stream.size(), 50000u);
  fs::create_directories(tmp.path() / "streamed");
  fs::create_directories(tmp.path() / "whole");
  std::move(stream).Write(tmp.path() / "streamed" / "dense.ply",
                          tmp.path() / "streamed" / "dense.ply.vis");
  WritePly(tmp.path() / "whole" / "dense.ply", cloud);
  WritePointVisibility(tmp.path() / "whole" / "dense.ply.vis", visibility);
  for (const char* name : {"dense.ply", "dense.ply.vis"})
    EXPECT_EQ(Bytes(tmp.path() / "streamed" / name), Bytes(tmp.path() / "whole" / name)) << name;
  EXPECT_EQ(ReadPly(tmp.path() / "streamed" / "dense.ply").points.size(), 50000u);
  EXPECT_EQ(ReadPointVisibility(tmp.path() / "streamed" / "dense.ply.vis"), visibility);
}

TEST(PointCloudStream, AnEmptyStreamWritesAnEmptyCloud) {
  testing::TempDir tmp("point_cloud_stream_empty");
  PointCloudStream stream(tmp.path());
  std::move(stream).Write(tmp.path() / "dense.ply", tmp.path() / "dense.ply.vis");
  EXPECT_TRUE(ReadPly(tmp.path() / "dense.ply").points.empty());
  EXPECT_TRUE(ReadPointVisibility(tmp.path() / "dense.ply.vis").empty());
}

}  // namespace
}  // namespace varsfm
