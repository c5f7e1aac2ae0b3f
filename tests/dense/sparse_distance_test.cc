#include "varsfm/dense/sparse_distance.h"

#include <gtest/gtest.h>

#include "varsfm/util/error.h"

namespace varsfm {
namespace {

// One registered camera at the origin looking down +z, and sparse points on the plane z = 4 on
// a 0.2 grid: the median depth (scene unit) is 4.
Reconstruction PlaneModel() {
  Reconstruction rec;
  Camera camera = Camera::FromFocal(640, 480, 500);
  rec.AddCamera(camera);
  Image image;
  image.image_id = 1;
  image.camera_id = camera.camera_id;
  image.registered = true;
  image.points2D.resize(21 * 21);
  rec.AddImage(image);
  point2D_t idx = 0;
  for (int i = -10; i <= 10; ++i)
    for (int j = -10; j <= 10; ++j) rec.AddPoint3D({0.2 * i, 0.2 * j, 4.0}, {{1, idx++}});
  return rec;
}

TEST(SparseDistance, MeasuresOffsetsFromTheSparseSurfaceInSceneUnits) {
  const Reconstruction rec = PlaneModel();
  // Dense points 0.02 in front of the plane, at grid-cell centres (0.1 from the grid points in
  // x and y): nearest-point distance sqrt(0.1^2 + 0.1^2 + 0.02^2), plane distance 0.02.
  std::vector<Eigen::Vector3d> dense;
  for (int i = -8; i < 8; ++i)
    for (int j = -8; j < 8; ++j) dense.emplace_back(0.2 * i + 0.1, 0.2 * j + 0.1, 3.98);
  const SparseDistanceStats s = MeasureAgainstSparse(dense, rec);
  EXPECT_EQ(s.num_checked, dense.size());
  EXPECT_NEAR(s.scene_depth, 4.0, 1e-9);
  EXPECT_NEAR(s.median_nearest, std::sqrt(0.02 + 0.0004) / 4.0, 1e-9);
  EXPECT_NEAR(s.median_plane, 0.02 / 4.0, 1e-9);
  EXPECT_DOUBLE_EQ(s.fraction_within_1pc, 1.0);  // 0.5 % of the depth
}

TEST(SparseDistance, SubsamplesDeterministically) {
  const Reconstruction rec = PlaneModel();
  std::vector<Eigen::Vector3d> dense;
  for (int i = 0; i < 1000; ++i) dense.emplace_back(0.001 * i, 0.0, 4.0 + 0.0001 * (i % 7));
  const SparseDistanceStats a = MeasureAgainstSparse(dense, rec, 8, 100);
  const SparseDistanceStats b = MeasureAgainstSparse(dense, rec, 8, 100);
  EXPECT_EQ(a.num_checked, 100u);
  EXPECT_EQ(a.median_plane, b.median_plane);
  EXPECT_EQ(a.median_nearest, b.median_nearest);
}

TEST(SparseDistance, RejectsEmptyInput) {
  EXPECT_THROW(MeasureAgainstSparse({{0, 0, 4}}, Reconstruction{}), Error);
  EXPECT_THROW(MeasureAgainstSparse({}, PlaneModel()), Error);
}

}  // namespace
}  // namespace varsfm
