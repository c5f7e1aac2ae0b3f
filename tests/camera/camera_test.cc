#include "varsfm/camera/camera.h"

#include <gtest/gtest.h>

#include "varsfm/camera/colmap_models.h"
#include "varsfm/camera/image_size.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

Camera TestCamera() {
  Camera c = Camera::FromFocal(1024, 683, 900.0);
  c.params = {900.0, 1.02, 0.5, 515.0, 340.0, -0.12, 0.03};
  return c;
}

TEST(Camera, KMatchesParameters) {
  const Camera c = TestCamera();
  const Eigen::Matrix3d K = c.K();
  EXPECT_DOUBLE_EQ(K(0, 0), 900.0);
  EXPECT_DOUBLE_EQ(K(1, 1), 900.0 * 1.02);
  EXPECT_DOUBLE_EQ(K(0, 1), 0.5);
  EXPECT_DOUBLE_EQ(K(0, 2), 515.0);
  EXPECT_DOUBLE_EQ(K(1, 2), 340.0);
  Camera d = Camera::FromFocal(10, 10, 1.0);
  d.SetK(K);
  EXPECT_NEAR(d.params[Camera::kAspect], 1.02, 1e-12);
}

TEST(Camera, ProjectionWithoutDistortionIsKTimesNormalised) {
  Camera c = TestCamera();
  c.params[Camera::kK1] = c.params[Camera::kK2] = 0;
  const Eigen::Vector3d X(0.3, -0.2, 2.5);
  const Eigen::Vector3d x = c.K() * X;
  EXPECT_TRUE(c.Project(X).isApprox(x.hnormalized(), 1e-12));
}

// A point projects into the resized image at the scaled pixel (pixel-corner origin), distortion
// included, with a different factor across and down.
TEST(Camera, ResizedProjectsAtTheScaledPixel) {
  const Camera c = TestCamera();
  const Camera r = c.Resized(c.width / 4, c.height / 2);
  EXPECT_EQ(r.width, c.width / 4);
  EXPECT_EQ(r.height, c.height / 2);
  const double sx = static_cast<double>(r.width) / c.width;
  const double sy = static_cast<double>(r.height) / c.height;
  for (const Eigen::Vector3d& X : {Eigen::Vector3d(0.3, -0.2, 2.5), Eigen::Vector3d(-1, 0.5, 4)}) {
    const Eigen::Vector2d p = c.Project(X), q = r.Project(X);
    EXPECT_NEAR(q.x(), sx * p.x(), 1e-9);
    EXPECT_NEAR(q.y(), sy * p.y(), 1e-9);
  }
}

TEST(SizeWithin, CapsTheLongerSideAndNeverEnlarges) {
  const Camera landscape = Camera::FromFocal(4000, 3000, 3000.0);
  const ScaledSize small = SizeWithin(landscape, 1000);
  EXPECT_DOUBLE_EQ(small.scale, 0.25);
  EXPECT_EQ(small.width, 1000);
  EXPECT_EQ(small.height, 750);
  const ScaledSize portrait = SizeWithin(Camera::FromFocal(3000, 4001, 3000.0), 800);
  EXPECT_EQ(portrait.height, 800);
  EXPECT_EQ(portrait.width, 600);  // 3000 x 800 / 4001 = 599.85, rounded
  const ScaledSize as_is = SizeWithin(landscape, 5000);
  EXPECT_EQ(as_is.scale, 1.0);
  EXPECT_EQ(as_is.width, 4000);
  EXPECT_EQ(as_is.height, 3000);
  EXPECT_EQ(SizeWithin(Camera::FromFocal(1000, 2, 1000.0), 10).height, 1);  // at least a pixel
}

TEST(Camera, UnprojectInvertsProjectWithDistortion) {
  const Camera c = TestCamera();
  for (double x = -0.5; x <= 0.5; x += 0.1) {
    for (double y = -0.35; y <= 0.35; y += 0.07) {
      const Eigen::Vector2d n(x, y);
      const Eigen::Vector2d pixel = c.NormalizedToImage(n);
      EXPECT_LT((c.ImageToNormalized(pixel) - n).norm(), 1e-10) << x << " " << y;
    }
  }
}

TEST(ColmapModels, RoundTripThroughSmallestModel) {
  Camera c = TestCamera();
  c.params[Camera::kSkew] = 0;
  for (int variant = 0; variant < 4; ++variant) {
    Camera v = c;
    if (variant == 0) v.params[Camera::kK1] = v.params[Camera::kK2] = 0;
    if (variant == 1) v.params[Camera::kK2] = 0;
    if (variant >= 2) v.params[Camera::kAspect] = variant == 2 ? 1.0 : 1.05;
    const int model = SmallestColmapModel(v);
    const Camera back = CameraFromColmap(model, ToColmapParams(v, model), v.width, v.height);
    for (int i = 0; i < Camera::kNumParams; ++i)
      EXPECT_NEAR(back.params[i], v.params[i], 1e-12) << "variant " << variant << " param " << i;
  }
  EXPECT_EQ(ColmapModelName(kColmapSimpleRadial), "SIMPLE_RADIAL");
  EXPECT_EQ(ColmapModelIdFromName("OPENCV"), kColmapOpenCV);
}

TEST(ColmapModels, RejectsUnsupportedModelsAndWrongCounts) {
  EXPECT_THROW(CameraFromColmap(5, {1, 2, 3, 4, 5, 6, 7, 8}, 10, 10), Error);
  EXPECT_THROW(CameraFromColmap(kColmapPinhole, {1, 2, 3}, 10, 10), Error);
}

}  // namespace
}  // namespace varsfm
