#include "varsfm/io/ply.h"

#include <gtest/gtest.h>

#include <fstream>
#include <limits>

#include "io/synthetic_model.h"
#include "support/test_data.h"
#include "varsfm/io/colmap_model.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;

PointCloud TestCloud() {
  PointCloud cloud;
  for (int i = 0; i < 50; ++i) {
    cloud.points.emplace_back(0.1 * i, -2.0 + i, 1e3 + 0.25 * i);
    cloud.normals.push_back(Eigen::Vector3d(i, 1, 2).normalized());
    cloud.colors.emplace_back(i, 255 - i, 3 * i);
  }
  return cloud;
}

TEST(Ply, DoubleRoundTripIsExact) {
  const PointCloud cloud = TestCloud();
  testing::TempDir tmp("ply_double");
  WritePly(tmp.path() / "c.ply", cloud, {.double_precision = true});
  const PointCloud back = ReadPly(tmp.path() / "c.ply");
  EXPECT_EQ(back.points, cloud.points);
  EXPECT_EQ(back.normals, cloud.normals);
  EXPECT_EQ(back.colors, cloud.colors);
}

TEST(Ply, FloatRoundTripWithinFloatPrecision) {
  const PointCloud cloud = TestCloud();
  testing::TempDir tmp("ply_float");
  WritePly(tmp.path() / "c.ply", cloud);
  // 50 vertices of 6 floats + 3 bytes after the header: the layout viewers expect.
  std::ifstream in(tmp.path() / "c.ply", std::ios::binary);
  std::string header, line;
  while (std::getline(in, line) && line != "end_header") header += line + "\n";
  EXPECT_NE(header.find("format binary_little_endian 1.0"), std::string::npos);
  EXPECT_NE(header.find("element vertex 50"), std::string::npos);
  EXPECT_NE(header.find("property float x"), std::string::npos);
  EXPECT_NE(header.find("property uchar red"), std::string::npos);
  const auto data_start = static_cast<size_t>(in.tellg());
  EXPECT_EQ(fs::file_size(tmp.path() / "c.ply") - data_start, 50u * (6 * 4 + 3));
  const PointCloud back = ReadPly(tmp.path() / "c.ply");
  ASSERT_EQ(back.points.size(), cloud.points.size());
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    EXPECT_LT((back.points[i] - cloud.points[i]).norm(), 1e-7 * cloud.points[i].norm());
    EXPECT_LT((back.normals[i] - cloud.normals[i]).norm(), 1e-7);
    EXPECT_EQ(back.colors[i], cloud.colors[i]);
  }
}

TEST(Ply, SparseModelPointsWithColoursNoNormals) {
  SyntheticOptions o;
  o.num_images = 3;
  o.num_points = 100;
  const Reconstruction rec = testing::ModelFromSynthetic(GenerateSyntheticScene(o));
  testing::TempDir tmp("ply_sparse");
  WritePly(rec, tmp.path() / "sparse.ply", {.double_precision = true});
  const PointCloud back = ReadPly(tmp.path() / "sparse.ply");
  EXPECT_FALSE(back.HasNormals());
  ASSERT_EQ(back.points.size(), rec.points3D().size());
  size_t i = 0;
  for (const auto& [id, point] : rec.points3D()) {
    EXPECT_EQ(back.points[i], point.xyz);
    EXPECT_EQ(back.colors[i], point.color);
    ++i;
  }
}

TEST(Ply, ReadsAsciiAndRejectsBadInput) {
  testing::TempDir tmp("ply_ascii");
  std::ofstream(tmp.path() / "a.ply") << "ply\nformat ascii 1.0\nelement vertex 2\n"
                                         "property float x\nproperty float y\nproperty float z\n"
                                         "property uchar red\nproperty uchar green\n"
                                         "property uchar blue\nelement face 0\n"
                                         "property list uchar int vertex_indices\nend_header\n"
                                         "1 2 3 10 20 30\n4 5 6 40 50 60\n";
  const PointCloud cloud = ReadPly(tmp.path() / "a.ply");
  ASSERT_EQ(cloud.points.size(), 2u);
  EXPECT_EQ(cloud.points[1], Eigen::Vector3d(4, 5, 6));
  EXPECT_EQ(cloud.colors[1], (Eigen::Matrix<uint8_t, 3, 1>(40, 50, 60)));
  std::ofstream(tmp.path() / "b.ply") << "not a ply\n";
  EXPECT_THROW(ReadPly(tmp.path() / "b.ply"), Error);
  EXPECT_THROW(ReadPly(tmp.path() / "absent.ply"), Error);
  PointCloud mismatched = TestCloud();
  mismatched.colors.pop_back();
  EXPECT_THROW(WritePly(tmp.path() / "m.ply", mismatched), Error);
  EXPECT_FALSE(fs::exists(tmp.path() / "m.ply"));
}

TEST(Ply, VisibilityRoundTripAndBadIndexRefused) {
  PointCloud cloud = TestCloud();
  cloud.viewpoints = {{0, 0, -5}, {1.5, 0.25, -4}, {-2, 1, -3}};
  for (size_t i = 0; i < cloud.points.size(); ++i)
    cloud.visibility.push_back(i % 2 ? std::vector<uint32_t>{0, 2}
                                     : std::vector<uint32_t>{static_cast<uint32_t>(i % 3)});
  testing::TempDir tmp("ply_visibility");
  WritePly(tmp.path() / "v.ply", cloud);
  const PointCloud back = ReadPly(tmp.path() / "v.ply");
  EXPECT_EQ(back.viewpoints, cloud.viewpoints);
  EXPECT_EQ(back.visibility, cloud.visibility);
  EXPECT_EQ(back.colors, cloud.colors);
  ASSERT_EQ(back.points.size(), cloud.points.size());
  EXPECT_LT((back.points[7] - cloud.points[7]).norm(), 1e-7 * cloud.points[7].norm());
  cloud.visibility[3] = {3};  // names no viewpoint
  EXPECT_THROW(WritePly(tmp.path() / "bad.ply", cloud), Error);
  EXPECT_FALSE(fs::exists(tmp.path() / "bad.ply"));
  std::ofstream(tmp.path() / "a.ply") << "ply\nformat ascii 1.0\nelement vertex 1\n"
                                         "property float x\nproperty float y\nproperty float z\n"
                                         "property list uchar uint visibility\n"
                                         "element viewpoint 1\nproperty double x\n"
                                         "property double y\nproperty double z\nend_header\n"
                                         "1 2 3 2 0 1\n0 0 0\n";
  EXPECT_THROW(ReadPly(tmp.path() / "a.ply"), Error);
}

// A NaN or an infinity crashed screened Poisson and hung the grids downstream: the reader
// refuses it with one line naming the file and the vertex, for points, normals and viewpoints.
TEST(Ply, NonFiniteValuesAreRefusedNamingTheVertex) {
  testing::TempDir tmp("ply_non_finite");
  const auto expect_error = [](const PointCloud& cloud, const fs::path& file,
                               const std::string& words) {
    WritePly(file, cloud, {.double_precision = true});
    try {
      ReadPly(file);
      ADD_FAILURE() << "no error for " << words;
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(file.string()), std::string::npos) << message;
      EXPECT_NE(message.find(words), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  };
  PointCloud nan = TestCloud();
  nan.points[7].y() = std::numeric_limits<double>::quiet_NaN();
  expect_error(nan, tmp.path() / "nan.ply", "has non-finite coordinates (vertex 7)");
  PointCloud inf = TestCloud();
  inf.points[0].x() = -std::numeric_limits<double>::infinity();
  expect_error(inf, tmp.path() / "inf.ply", "has non-finite coordinates (vertex 0)");
  PointCloud normal = TestCloud();
  normal.normals[3].z() = std::numeric_limits<double>::infinity();
  expect_error(normal, tmp.path() / "normal.ply", "has a non-finite normal (vertex 3)");
  PointCloud viewpoint = TestCloud();
  viewpoint.viewpoints = {{0, 0, -5}, {0, std::numeric_limits<double>::quiet_NaN(), 0}};
  viewpoint.visibility.assign(viewpoint.points.size(), {0});
  expect_error(viewpoint, tmp.path() / "viewpoint.ply", "viewpoint 1 has non-finite coordinates");
}

TEST(Ply, ReadsColmapsPlyExport) {
  if (testing::RunCommand("colmap help") != 0) GTEST_SKIP() << "colmap is not installed; skipping";
  SyntheticOptions o;
  o.num_images = 3;
  o.num_points = 100;
  const Reconstruction rec = testing::ModelFromSynthetic(GenerateSyntheticScene(o));
  testing::TempDir tmp("ply_colmap");
  WriteColmapModel(rec, tmp.path() / "model");
  std::string output;
  ASSERT_EQ(testing::RunCommand("colmap model_converter --input_path " +
                                    (tmp.path() / "model").string() + " --output_path " +
                                    (tmp.path() / "colmap.ply").string() + " --output_type PLY",
                                &output),
            0)
      << output;
  const PointCloud back = ReadPly(tmp.path() / "colmap.ply");
  ASSERT_EQ(back.points.size(), rec.points3D().size());
  // COLMAP writes its points in hash-map order: find each of ours among them.
  for (const auto& [id, point] : rec.points3D()) {
    // Captured by name: clang before 16 cannot capture a structured binding.
    const Eigen::Vector3d& xyz = point.xyz;
    const auto it = std::find_if(back.points.begin(), back.points.end(), [&](const auto& x) {
      return (x - xyz).norm() < 1e-6 * std::max(1.0, xyz.norm());
    });
    ASSERT_NE(it, back.points.end()) << "point " << id;
    EXPECT_EQ(back.colors[it - back.points.begin()], point.color);
  }
}

}  // namespace
}  // namespace varsfm
