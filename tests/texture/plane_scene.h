#pragma once
// A plane z = 0, x and y in [-1, 1], painted with a smooth colour pattern and photographed by
// pinhole cameras with a chosen exposure each: the exact truth for view selection, exposure and
// seam levelling tests (the colour any view should show of a point is known in closed form).
#include <cmath>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "synthetic_mesh.h"
#include "varsfm/texture/face_observations.h"

namespace varsfm::testing {

// BGR colour of the plane at (x, y): low-frequency, so a seam is a visible jump.
inline Eigen::Vector3f PlaneColour(double x, double y) {
  return Eigen::Vector3f(static_cast<float>(100 + 50 * std::sin(2 * x + 1)),
                         static_cast<float>(120 + 40 * std::cos(3 * y)),
                         static_cast<float>(90 + 30 * std::sin(x + y)));
}

inline TriangleMesh PlaneMesh(double cell = 0.1) {
  TriangleMesh mesh;
  AddGridQuad({-1, -1, 0}, {2, 0, 0}, {0, 2, 0}, cell, &mesh);
  return mesh;
}

// A 200 x 200 view from `centre` looking at `target`, its photo at `exposure` x the plane's
// colour (black off the plane).
inline PosedCamera PlaneView(const Eigen::Vector3d& centre, const Eigen::Vector3d& target) {
  return {Camera::FromFocal(200, 200, 150), LookAt(centre, target)};
}

inline cv::Mat PhotographPlane(const PosedCamera& view, double exposure) {
  cv::Mat image(view.camera.height, view.camera.width, CV_8UC3, cv::Scalar::all(0));
  const Eigen::Matrix3d world_from_cam = view.cam_from_world.R().transpose();
  const Eigen::Vector3d centre = view.cam_from_world.Center();
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      const Eigen::Vector2d n = view.camera.ImageToNormalized(Eigen::Vector2d(x + 0.5, y + 0.5));
      const Eigen::Vector3d ray = world_from_cam * n.homogeneous();
      if (std::abs(ray.z()) < 1e-12) continue;
      const double t = -centre.z() / ray.z();
      const Eigen::Vector3d p = centre + t * ray;
      if (t <= 0 || std::abs(p.x()) > 1 || std::abs(p.y()) > 1) continue;
      const Eigen::Vector3f c = PlaneColour(p.x(), p.y()) * static_cast<float>(exposure);
      image.at<cv::Vec3b>(y, x) =
          cv::Vec3b(cv::saturate_cast<uchar>(c[0]), cv::saturate_cast<uchar>(c[1]),
                    cv::saturate_cast<uchar>(c[2]));
    }
  }
  return image;
}

}  // namespace varsfm::testing
