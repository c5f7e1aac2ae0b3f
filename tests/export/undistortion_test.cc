#include "varsfm/export/undistortion.h"

#include <gtest/gtest.h>

#include "export/scene.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

Camera DistortedCamera() {
  Camera camera = Camera::FromFocal(320, 240, 300);
  camera.camera_id = 1;
  camera.params[Camera::kAspect] = 1.02;
  camera.params[Camera::kSkew] = 0.8;
  camera.params[Camera::kU0] += 5;
  camera.params[Camera::kV0] -= 3;
  camera.params[Camera::kK1] = -0.12;
  camera.params[Camera::kK2] = 0.03;
  return camera;
}

// Within a hundredth of a pixel: the border is traced at discrete samples.
bool InsidePhoto(const Camera& camera, const Eigen::Vector2d& p) {
  constexpr double kTolerance = 0.01;
  return p.x() >= -kTolerance && p.y() >= -kTolerance && p.x() <= camera.width + kTolerance &&
         p.y() <= camera.height + kTolerance;
}

// How the pinhole's rectangle sits in the photo: whether its border, traced at 101 points a
// side, sees only rays the photo saw, and on which sides one more pixel leaves the photo.
struct RectangleFit {
  bool inside = true;
  bool left_tight = false, right_tight = false, top_tight = false, bottom_tight = false;
};

RectangleFit FitOf(const Camera& camera, const Camera& pinhole) {
  const auto inside = [&](double x, double y) {
    return InsidePhoto(camera, camera.NormalizedToImage(pinhole.ImageToNormalized({x, y})));
  };
  RectangleFit fit;
  for (int i = 0; i <= 100; ++i) {
    const double sx = pinhole.width * i / 100.0;
    const double sy = pinhole.height * i / 100.0;
    fit.inside &=
        inside(0, sy) && inside(pinhole.width, sy) && inside(sx, 0) && inside(sx, pinhole.height);
    fit.left_tight |= !inside(-1.0, sy);
    fit.right_tight |= !inside(pinhole.width + 1.0, sy);
    fit.top_tight |= !inside(sx, -1.0);
    fit.bottom_tight |= !inside(sx, pinhole.height + 1.0);
  }
  return fit;
}

// The largest difference (grey levels) between the photo undistorted to `pinhole` and the exact
// colour of each of its pixels' rays, the image's outermost 2 pixels aside.
double MaxRayColourError(const Camera& camera, const Camera& pinhole) {
  const cv::Mat undistorted = UndistortImage(testing::RenderRayPattern(camera), camera, pinhole);
  EXPECT_EQ(undistorted.cols, pinhole.width);
  EXPECT_EQ(undistorted.rows, pinhole.height);
  double max_error = 0;
  for (int y = 2; y < pinhole.height - 2; ++y) {
    for (int x = 2; x < pinhole.width - 2; ++x) {
      const double expected = testing::RayPattern(pinhole.ImageToNormalized({x + 0.5, y + 0.5}));
      max_error = std::max(max_error, std::abs(undistorted.at<cv::Vec3b>(y, x)[1] - expected));
    }
  }
  return max_error;
}

TEST(Undistortion, PinholeKeepsFocalAndDropsSkewAndDistortion) {
  const Camera camera = DistortedCamera();
  const Camera pinhole = UndistortedPinholeCamera(camera);
  EXPECT_EQ(pinhole.camera_id, camera.camera_id);
  EXPECT_DOUBLE_EQ(pinhole.focal(), camera.focal());
  EXPECT_DOUBLE_EQ(pinhole.fy(), camera.fy());
  EXPECT_EQ(pinhole.params[Camera::kSkew], 0.0);
  EXPECT_FALSE(pinhole.HasDistortion());
}

// Every pixel of the undistorted image sees a ray the photo saw (no blank border), and the
// rectangle is the largest such: one more pixel on any side leaves the photo somewhere.
TEST(Undistortion, RectangleIsInsideThePhotoAndTight) {
  const Camera camera = DistortedCamera();
  const Camera pinhole = UndistortedPinholeCamera(camera);
  ASSERT_GT(pinhole.width, 200);
  ASSERT_GT(pinhole.height, 150);
  const RectangleFit fit = FitOf(camera, pinhole);
  EXPECT_TRUE(fit.inside);
  EXPECT_TRUE(fit.left_tight && fit.right_tight && fit.top_tight && fit.bottom_tight);
}

TEST(Undistortion, PixelsMoveToThePinholeProjection) {
  const Camera camera = DistortedCamera();
  const Camera pinhole = UndistortedPinholeCamera(camera);
  for (const Eigen::Vector3d& x :
       {Eigen::Vector3d(0.2, -0.1, 1.0), Eigen::Vector3d(-0.3, 0.25, 1.5),
        Eigen::Vector3d(0.0, 0.0, 2.0)}) {
    const Eigen::Vector2d undistorted = UndistortPixel(camera, pinhole, camera.Project(x));
    EXPECT_LT((undistorted - pinhole.Project(x)).norm(), 1e-6);
  }
}

TEST(Undistortion, ImageShowsEachRaysColour) {
  const Camera camera = DistortedCamera();
  // Interpolation of the pattern plus rounding; a half-pixel shift would be ~15.
  EXPECT_LT(MaxRayColourError(camera, UndistortedPinholeCamera(camera)), 4.0);
}

// Centred: the principal point at the exact centre, every pixel inside the photo, and the
// rectangle as large as the principal point's nearer edge on each axis allows.
TEST(Undistortion, CentredRectangleIsInsideThePhotoAroundThePrincipalPoint) {
  Camera camera = DistortedCamera();
  camera.params[Camera::kU0] += 40;  // well off-centre: the left side bounds the width
  const Camera kept = UndistortedPinholeCamera(camera);
  const Camera pinhole = UndistortedPinholeCamera(camera, PrincipalPointPlacement::kCentred);
  EXPECT_EQ(pinhole.PrincipalPointOffset(), Eigen::Vector2d::Zero());
  EXPECT_DOUBLE_EQ(pinhole.focal(), camera.focal());
  EXPECT_LT(pinhole.width, kept.width - 40);
  EXPECT_GT(pinhole.width, kept.width - 100);
  const RectangleFit fit = FitOf(camera, pinhole);
  EXPECT_TRUE(fit.inside);
  // One more pixel on both sides of an axis leaves the photo somewhere.
  EXPECT_TRUE(fit.left_tight || fit.right_tight);
  EXPECT_TRUE(fit.top_tight || fit.bottom_tight);
  // The resampled photo shows each ray's colour there too.
  EXPECT_LT(MaxRayColourError(camera, pinhole), 4.0);
}

TEST(Undistortion, CentringAPrincipalPointOutsideThePhotoFails) {
  Camera camera = DistortedCamera();
  camera.params[Camera::kU0] = -20;
  EXPECT_THROW(UndistortedPinholeCamera(camera, PrincipalPointPlacement::kCentred), Error);
  EXPECT_NO_THROW(UndistortedPinholeCamera(camera));
}

TEST(Undistortion, ImageOfAnotherSizeIsRefused) {
  const Camera camera = DistortedCamera();
  EXPECT_THROW(UndistortImage(cv::Mat(10, 10, CV_8UC3), camera, UndistortedPinholeCamera(camera)),
               Error);
}

}  // namespace
}  // namespace varsfm
