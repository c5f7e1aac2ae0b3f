// Model and point-cloud files that crashed, hung or hit undefined behaviour in the readers (found
// by fuzz/colmap_binary_fuzzer.cc's smoke run, and by reviewing the readers for what
// fuzz/ply_fuzzer.cc and mesh_ply_fuzzer.cc target): each is now one varsfm::Error (or a defined
// value), before anything is sized from the file. docs/robustness.md lists them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include "support/test_data.h"
#include "varsfm/io/colmap_model.h"
#include "varsfm/io/ply.h"
#include "varsfm/io/ply_format.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

template <typename T>
void Put(std::string* out, T value) {  // little-endian hosts, as COLMAP's files
  out->append(reinterpret_cast<const char*>(&value), sizeof(T));
}

void WriteText(const fs::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary) << bytes;
}

// cameras.bin with camera 1 (SIMPLE_PINHOLE 64 x 48, focal `focal`).
std::string OneCamera(double focal = 50.0) {
  std::string bytes;
  Put<uint64_t>(&bytes, 1);
  Put<uint32_t>(&bytes, 1);
  Put<int32_t>(&bytes, 0);
  Put<uint64_t>(&bytes, 64);
  Put<uint64_t>(&bytes, 48);
  for (double p : {focal, 32.0, 24.0}) Put<double>(&bytes, p);
  return bytes;
}

// images.bin with image 1 of camera 1, quaternion `qw` (x = y = z = 0) and `num_points` declared
// 2D points, none present.
std::string OneImage(uint64_t num_points, double qw = 1.0) {
  std::string bytes;
  Put<uint64_t>(&bytes, 1);
  Put<uint32_t>(&bytes, 1);
  for (double v : {qw, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0}) Put<double>(&bytes, v);
  Put<uint32_t>(&bytes, 1);
  bytes += std::string("a.jpg", 6);  // with its NUL
  Put<uint64_t>(&bytes, num_points);
  return bytes;
}

// points3D.bin with one point at (x, 0, 0) and an empty track.
std::string OnePoint(double x) {
  std::string bytes;
  Put<uint64_t>(&bytes, 1);
  Put<uint64_t>(&bytes, 1);
  for (double v : {x, 0.0, 0.0}) Put<double>(&bytes, v);
  bytes += "abc";
  Put<double>(&bytes, 0.5);
  Put<uint64_t>(&bytes, 0);
  return bytes;
}

std::string ReadError(const fs::path& model) {
  try {
    ReadColmapModel(model);
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(CorruptColmapBinary, HugePointCountsAreRefusedBeforeAllocation) {
  TempDir dir("corrupt_colmap");
  const fs::path model = dir.path();
  std::string no_points;
  Put<uint64_t>(&no_points, 0);
  // 2^40 2D points in a 100-byte file: resized to 24 TB before the fix.
  WriteText(model / "cameras.bin", OneCamera());
  WriteText(model / "images.bin", OneImage(uint64_t{1} << 40));
  WriteText(model / "points3D.bin", no_points);
  EXPECT_THROW(ReadColmapModel(model), Error);

  // 2^40 3D points in an 8-byte file.
  WriteText(model / "images.bin", OneImage(0));
  std::string points;
  Put<uint64_t>(&points, uint64_t{1} << 40);
  WriteText(model / "points3D.bin", points);
  EXPECT_THROW(ReadColmapModel(model), Error);

  // One point whose track claims 2^61 elements.
  points.clear();
  Put<uint64_t>(&points, 1);
  Put<uint64_t>(&points, 1);
  for (int k = 0; k < 3; ++k) Put<double>(&points, 0.0);
  points += "abc";
  Put<double>(&points, 0.5);
  Put<uint64_t>(&points, uint64_t{1} << 61);
  WriteText(model / "points3D.bin", points);
  try {
    ReadColmapModel(model);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("track elements cannot fit"), std::string::npos)
        << e.what();
  }

  // The same files with honest counts are read.
  WriteText(model / "points3D.bin", no_points);
  EXPECT_EQ(ReadColmapModel(model).images().size(), 1u);
}

// A camera, a pose or a point that is not a finite number put NaN into every stage after (a
// dense cloud of NaN, a mesh refused far from the cause); the reader names it.
TEST(CorruptColmapBinary, NonFiniteCamerasPosesAndPointsAreRefused) {
  TempDir dir("nonfinite_colmap");
  const fs::path model = dir.path();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  WriteText(model / "cameras.bin", OneCamera());
  WriteText(model / "images.bin", OneImage(0));
  WriteText(model / "points3D.bin", OnePoint(1.0));
  ASSERT_EQ(ReadColmapModel(model).points3D().size(), 1u);

  WriteText(model / "cameras.bin", OneCamera(nan));
  EXPECT_NE(ReadError(model).find("not a finite number"), std::string::npos) << ReadError(model);
  WriteText(model / "cameras.bin", OneCamera(-50.0));
  EXPECT_NE(ReadError(model).find("focal length must be positive"), std::string::npos)
      << ReadError(model);
  WriteText(model / "cameras.bin", OneCamera());

  WriteText(model / "images.bin", OneImage(0, /*qw=*/0.0));
  EXPECT_NE(ReadError(model).find("pose is not finite"), std::string::npos) << ReadError(model);
  WriteText(model / "images.bin", OneImage(0));

  WriteText(model / "points3D.bin", OnePoint(std::numeric_limits<double>::infinity()));
  EXPECT_NE(ReadError(model).find("position is not a finite number"), std::string::npos)
      << ReadError(model);
}

TEST(CorruptPly, ElementWithoutPropertiesCannotClaimRecords) {
  TempDir dir("corrupt_ply");
  // Before the fix the mesh reader (texture/mesh_reader.cc, on the same header) looped 2^62
  // times over records of nothing, and this reader accepted the file.
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\n"
      "property float y\nproperty float z\nelement junk 4611686018427387904\nend_header\n";
  WriteText(dir.path() / "m.ply", header);
  try {
    ReadPly(dir.path() / "m.ply");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no properties"), std::string::npos) << e.what();
  }
}

TEST(CorruptPly, CountsBeyondTheDataAreRefusedFromTheHeader) {
  TempDir dir("corrupt_ply");
  // 2^32 - 1 vertices of 12 bytes in a file with 10 bytes of data.
  WriteText(dir.path() / "c.ply",
            "ply\nformat binary_little_endian 1.0\nelement vertex 4294967295\nproperty float x\n"
            "property float y\nproperty float z\nend_header\n0123456789");
  try {
    ReadPly(dir.path() / "c.ply");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("more than the data after it can hold"), std::string::npos)
        << e.what();
  }
  // A negative count reads as a huge one.
  WriteText(dir.path() / "c.ply",
            "ply\nformat ascii 1.0\nelement vertex -3\nproperty float x\nproperty float y\n"
            "property float z\nend_header\n1 2 3\n");
  EXPECT_THROW(ReadPly(dir.path() / "c.ply"), Error);
}

TEST(CorruptPly, ColoursOutOfByteRangeAreClamped) {
  // Converting 300, -5 or NaN to uint8_t was undefined behaviour.
  EXPECT_EQ(ply::ColorByte(300.0), 255);
  EXPECT_EQ(ply::ColorByte(-5.0), 0);
  EXPECT_EQ(ply::ColorByte(std::numeric_limits<double>::quiet_NaN()), 0);
  EXPECT_EQ(ply::ColorByte(1e300), 255);
  EXPECT_EQ(ply::ColorByte(17.9), 17);

  TempDir dir("corrupt_ply");
  std::string bytes =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n"
      "property float y\nproperty float z\nproperty float red\nproperty float green\n"
      "property float blue\nend_header\n";
  for (float v : {1.0f, 2.0f, 3.0f, 300.0f, -5.0f, std::numeric_limits<float>::quiet_NaN()})
    Put<float>(&bytes, v);
  WriteText(dir.path() / "c.ply", bytes);
  const PointCloud cloud = ReadPly(dir.path() / "c.ply");
  ASSERT_EQ(cloud.colors.size(), 1u);
  EXPECT_EQ(cloud.colors[0], (Eigen::Matrix<uint8_t, 3, 1>(255, 0, 0)));
}

TEST(CorruptPly, NonFiniteListCountIsMalformedData) {
  // A float list count of NaN was converted to size_t (undefined behaviour).
  std::string data;
  Put<float>(&data, std::numeric_limits<float>::quiet_NaN());
  std::istringstream in(data);
  ply::Element face{
      "face",
      1,
      {{"vertex_indices", "int", "float", ply::ScalarType::kInt32, ply::ScalarType::kFloat32}}};
  ply::ValueReader reader(in, /*binary=*/true);
  std::vector<double> scalars;
  std::vector<std::vector<double>> lists;
  EXPECT_FALSE(ply::ReadRecord(reader, face, &scalars, &lists));
}

}  // namespace
}  // namespace varsfm
