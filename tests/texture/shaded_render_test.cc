#include <gtest/gtest.h>

#include <cmath>

#include "varsfm/texture/render.h"

namespace varsfm {
namespace {

// A square of side 2 at depth 5, turned by `degrees` about the vertical axis, seen by a camera
// at the origin looking down +z.
void Square(double degrees, std::vector<Eigen::Vector3d>* vertices,
            std::vector<Eigen::Vector3i>* faces) {
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(degrees * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
  *vertices = {};
  for (const auto& corner : {Eigen::Vector3d(-1, -1, 0), Eigen::Vector3d(1, -1, 0),
                             Eigen::Vector3d(1, 1, 0), Eigen::Vector3d(-1, 1, 0)}) {
    vertices->push_back(turn * corner + Eigen::Vector3d(0, 0, 5));
  }
  *faces = {{0, 1, 2}, {0, 2, 3}};
}

TEST(RenderShadedMesh, LambertFromTheCameraAndBlackBackground) {
  const Camera camera = Camera::FromFocal(101, 101, 200);
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> faces;
  Square(0, &vertices, &faces);
  cv::Mat image = RenderShadedMesh(vertices, faces, camera, Rigid3d());
  // The centre pixel's ray is the face normal: full brightness; a corner sees nothing.
  EXPECT_EQ(image.at<cv::Vec3b>(50, 50)[0], 255);
  EXPECT_EQ(image.at<cv::Vec3b>(0, 0), cv::Vec3b(0, 0, 0));

  Square(60, &vertices, &faces);  // cos 60 = 0.5 at the centre
  image = RenderShadedMesh(vertices, faces, camera, Rigid3d());
  EXPECT_NEAR(image.at<cv::Vec3b>(50, 50)[0], 40 + 215 * 0.5, 1.0);
}

}  // namespace
}  // namespace varsfm
