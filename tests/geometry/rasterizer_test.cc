// The z-buffer keeps the nearest surface whatever the drawing order, shared edges are drawn
// once, and per-pixel barycentrics from rays are exact.
#include <gtest/gtest.h>

#include "varsfm/geometry/rasterizer.h"

namespace varsfm {
namespace {

Camera TestCamera() { return Camera::FromFocal(64, 48, 50.0); }

// A square at depth z in front of the camera, as two triangles.
void AddSquare(double z, double half, std::vector<Eigen::Vector3d>* vertices,
               std::vector<Eigen::Vector3i>* faces) {
  const int b = static_cast<int>(vertices->size());
  vertices->emplace_back(-half, -half, z);
  vertices->emplace_back(half, -half, z);
  vertices->emplace_back(half, half, z);
  vertices->emplace_back(-half, half, z);
  faces->emplace_back(b, b + 1, b + 2);
  faces->emplace_back(b, b + 2, b + 3);
}

TEST(Rasterizer, ZBufferKeepsTheNearestFaceInEitherOrder) {
  for (const bool near_first : {true, false}) {
    std::vector<Eigen::Vector3d> vertices;
    std::vector<Eigen::Vector3i> faces;
    // Near: half-size 0.25 at depth 2 (6.25 px either side of the centre); far: half-size 1 at
    // depth 4 (12.5 px), so the far square shows around the near one.
    if (near_first) {
      AddSquare(2.0, 0.25, &vertices, &faces);
      AddSquare(4.0, 1.0, &vertices, &faces);
    } else {
      AddSquare(4.0, 1.0, &vertices, &faces);
      AddSquare(2.0, 0.25, &vertices, &faces);
    }
    const FaceRaster r =
        RasterizeFaces(ProjectVertices(vertices, TestCamera(), Rigid3d()), faces, 64, 48);
    const int near_faces_begin = near_first ? 0 : 2;
    const int32_t centre = r.FaceAt(32, 24);
    EXPECT_GE(centre, near_faces_begin);
    EXPECT_LT(centre, near_faces_begin + 2);
    EXPECT_NEAR(r.DepthAt(32, 24), 2.0, 1e-5);
    // 10 px off centre: the far square only.
    const int32_t side = r.FaceAt(32 + 10, 24);
    EXPECT_GE(side, 2 - near_faces_begin);
    EXPECT_LT(side, 4 - near_faces_begin);
    EXPECT_NEAR(r.DepthAt(32 + 10, 24), 4.0, 1e-5);
    EXPECT_EQ(r.FaceAt(1, 1), -1);
  }
}

TEST(Rasterizer, SharedEdgesAreDrawnOnce) {
  // A square whose corners sit on pixel corners: its two triangles cover exactly its pixels
  // and each pixel once, including those whose centres lie on the diagonal.
  std::vector<ProjectedVertex> p(4);
  p[0].pixel = {10, 10};
  p[1].pixel = {30, 10};
  p[2].pixel = {30, 30};
  p[3].pixel = {10, 30};
  for (auto& v : p) v.depth = 1;
  const std::vector<Eigen::Vector3i> faces = {{0, 1, 2}, {0, 2, 3}};
  const FaceRaster r = RasterizeFaces(p, faces, 40, 40);
  int covered = 0;
  for (const int32_t f : r.face) covered += f >= 0;
  EXPECT_EQ(covered, 20 * 20);
  // Adjacent squares sharing a vertical edge: no pixel lost or doubled along it.
  std::vector<ProjectedVertex> q = p;
  q.resize(6);
  q[4].pixel = {20.5, 10};
  q[5].pixel = {20.5, 30};
  q[4].depth = q[5].depth = 1;
  const std::vector<Eigen::Vector3i> halves = {{0, 4, 5}, {0, 5, 3}, {4, 1, 2}, {4, 2, 5}};
  const FaceRaster h = RasterizeFaces(q, halves, 40, 40);
  covered = 0;
  for (const int32_t f : h.face) covered += f >= 0;
  EXPECT_EQ(covered, 20 * 20);
}

TEST(Rasterizer, FacesBehindTheCameraAreSkipped) {
  std::vector<Eigen::Vector3d> vertices = {{-1, -1, -2}, {1, -1, 2}, {0, 1, 2}};
  const FaceRaster r = RasterizeFaces(ProjectVertices(vertices, TestCamera(), Rigid3d()),
                                      {Eigen::Vector3i(0, 1, 2)}, 64, 48);
  for (const int32_t f : r.face) EXPECT_EQ(f, -1);
}

TEST(Rasterizer, RayBarycentricsAreExact) {
  const Eigen::Vector3d a(-1, -1, 3), b(2, -1, 5), c(0, 2, 4);
  const Eigen::Vector3d truth(0.2, 0.3, 0.5);
  const Eigen::Vector3d point = truth[0] * a + truth[1] * b + truth[2] * c;
  Eigen::Vector3d l;
  ASSERT_TRUE(FaceBarycentrics(a, b, c, point.hnormalized(), &l));
  EXPECT_NEAR((l - truth).norm(), 0.0, 1e-12);
}

}  // namespace
}  // namespace varsfm
