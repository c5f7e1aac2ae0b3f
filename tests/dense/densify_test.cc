#include "varsfm/dense/densify.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "dense/rendered_scene_truth.h"
#include "varsfm/synthetic/rendered_scene.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

using testing::PlaneDistance;

TEST(Densify, RenderedSceneLiesOnTheTrueSurfaces) {
  RenderedSceneOptions options;
  options.num_images = 4;
  options.width = 320;
  options.height = 240;
  options.focal_start = 256;  // the default 640 at 800 px, scaled to 320 px
  options.arc_degrees = 50;
  const RenderedScene scene = RenderSyntheticScene(options);
  const std::vector<SurfaceQuad>& quads = scene.surface;
  const Reconstruction rec = SparseModelFromRenderedScene(scene);
  ASSERT_GT(rec.points3D().size(), 100u);

  DensifyStats stats;
  DenseReconstructionOptions
      propagation;  // this test is about match propagation (the paper's method)
  propagation.method = DenseMethod::kPropagation;
  const PointCloud cloud = Densify(
      rec, [&](image_t id) { return scene.images[id - 1]; }, propagation, &stats);
  EXPECT_GE(stats.num_pairs, 2u);
  // Four 320x240 views: tens of thousands of pixels are matched and survive fusion.
  EXPECT_GT(cloud.points.size(), 20000u);
  ASSERT_EQ(cloud.normals.size(), cloud.points.size());
  ASSERT_EQ(cloud.colors.size(), cloud.points.size());
  // Visibility in the cloud: every view is a viewpoint at its camera centre; every point lists
  // at least the two views of its pair, ascending, each of which sees it in front.
  ASSERT_EQ(cloud.visibility.size(), cloud.points.size());
  ASSERT_EQ(cloud.viewpoints.size(), 4u);
  for (size_t v = 0; v < 4; ++v)
    EXPECT_LT((cloud.viewpoints[v] - scene.poses[v].Center()).norm(), 1e-9);
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    const std::vector<uint32_t>& views = cloud.visibility[i];
    ASSERT_GE(views.size(), 2u);
    ASSERT_TRUE(std::is_sorted(views.begin(), views.end()));
    for (uint32_t v : views) ASSERT_GT((scene.poses[v] * cloud.points[i]).z(), 0);
  }

  std::vector<double> distances, normal_angles;
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    Eigen::Vector3d n;
    distances.push_back(PlaneDistance(quads, cloud.points[i], &n));
    normal_angles.push_back(std::acos(std::min(1.0, std::abs(n.dot(cloud.normals[i])))) * 180 /
                            M_PI);
  }
  const auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  // A pixel spans ~5.2 / 256 = 0.02 scene units at the back wall; adjacent views differ in
  // scale by ~17 % (the zoom), so matches are ~0.3 px noisy and points about one pixel
  // footprint off their surface (measured: median 0.016, 90th percentile 0.079, normals'
  // median error 30 deg with the default 20 neighbours; random normals would give 60 deg).
  EXPECT_LT(median(distances), 0.025);
  EXPECT_LT(median(normal_angles), 40.0);
  std::sort(distances.begin(), distances.end());
  EXPECT_LT(distances[distances.size() * 9 / 10], 0.12);
}

TEST(Densify, RejectsModelsWithFewerThanTwoImages) {
  EXPECT_THROW(Densify(Reconstruction{}, [](image_t) { return cv::Mat(); }), Error);
  Reconstruction one;
  one.AddCamera(Camera::FromFocal(320, 240, 300));
  Image image;
  image.image_id = 1;
  image.camera_id = 0;
  image.registered = true;
  one.AddImage(image);
  EXPECT_THROW(Densify(one, [](image_t) { return cv::Mat(240, 320, CV_8UC3); }), Error);
}

TEST(Densify, UndistortionInvertsTheCameraModel) {
  // A photo of a grid drawn through the distorting camera: after undistortion each grid point
  // lies where the pinhole K puts it.
  Camera camera = Camera::FromFocal(320, 240, 250);
  camera.params[Camera::kK1] = -0.1;
  cv::Mat photo(240, 320, CV_8UC3, cv::Scalar::all(0));
  const Eigen::Vector2d n(0.2, -0.15);
  const Eigen::Vector2d distorted = camera.NormalizedToImage(n);
  cv::circle(photo, cv::Point2d(distorted.x() - 0.5, distorted.y() - 0.5), 2, cv::Scalar::all(255),
             cv::FILLED);
  const UndistortedView view = UndistortImage(photo, camera, 0.5);
  const Eigen::Vector2d expected = (view.K * n.homogeneous()).hnormalized();
  cv::Moments m = cv::moments(view.gray, false);
  ASSERT_GT(m.m00, 0);
  EXPECT_NEAR(m.m10 / m.m00 + 0.5, expected.x(), 0.2);
  EXPECT_NEAR(m.m01 / m.m00 + 0.5, expected.y(), 0.2);
  EXPECT_EQ(view.gray.cols, 160);
}

}  // namespace
}  // namespace varsfm
