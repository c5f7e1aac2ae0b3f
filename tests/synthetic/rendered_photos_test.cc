#include <algorithm>
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "varsfm/synthetic/rendered_scene.h"

namespace varsfm {
namespace {

RenderedSceneOptions PhotoOptions() {
  RenderedSceneOptions options;
  options.path = CameraPath::kPhotos;
  options.num_images = 40;
  options.street_step = 0.5;  // a 19.5 m street
  options.width = 96;
  options.height = 72;
  options.focal_start = 76.8;
  options.zoom = 1.6;
  options.supersampling = 1;
  return options;
}

// The unordered collection: positions spread over the whole street with no order by index,
// every camera looking at the facade (z = 4) from 3-5 m, focal lengths within x1 .. x1.6.
TEST(RenderedPhotos, RandomPositionsDirectionsAndFocalLengths) {
  const RenderedSceneOptions options = PhotoOptions();
  const RenderedScene scene = RenderSyntheticScene(options);
  ASSERT_EQ(scene.images.size(), 40u);
  const double length = options.street_step * (options.num_images - 1);
  int increasing = 0;
  double min_x = 1e9, max_x = -1e9, min_f = 1e9, max_f = 0;
  for (size_t i = 0; i < scene.poses.size(); ++i) {
    const Eigen::Vector3d c = scene.poses[i].Center();
    min_x = std::min(min_x, c.x());
    max_x = std::max(max_x, c.x());
    EXPECT_GE(4.0 - c.z(), 3.0 - 1e-9);
    EXPECT_LE(4.0 - c.z(), 5.0 + 1e-9);
    // Optical axis (third row of R) towards the facade, within 35 deg of its normal in yaw.
    const Eigen::Vector3d axis = scene.poses[i].R().row(2).transpose();
    EXPECT_GT(axis.z(), 0.0);
    EXPECT_LE(std::abs(std::atan2(axis.x(), axis.z())), 35.0 * std::numbers::pi / 180.0 + 1e-9);
    const double f = scene.cameras[i].focal();
    min_f = std::min(min_f, f);
    max_f = std::max(max_f, f);
    if (i > 0 && c.x() > scene.poses[i - 1].Center().x()) ++increasing;
  }
  EXPECT_LT(min_x, 0.2 * length);
  EXPECT_GT(max_x, 0.8 * length);
  EXPECT_GE(min_f, options.focal_start - 1e-9);
  EXPECT_LE(max_f, options.zoom * options.focal_start + 1e-9);
  EXPECT_GT(max_f - min_f, 0.3 * options.focal_start);
  // An ordered walk would step forward 39 times; random order about half of them.
  EXPECT_GT(increasing, 8);
  EXPECT_LT(increasing, 31);
}

TEST(RenderedPhotos, SameSeedSameCollection) {
  const RenderedScene a = RenderSyntheticScene(PhotoOptions());
  const RenderedScene b = RenderSyntheticScene(PhotoOptions());
  RenderedSceneOptions other = PhotoOptions();
  other.seed += 1;
  const RenderedScene c = RenderSyntheticScene(other);
  for (size_t i = 0; i < a.poses.size(); ++i) {
    EXPECT_EQ(a.poses[i].Center(), b.poses[i].Center());
    EXPECT_EQ(cv::norm(a.images[i], b.images[i], cv::NORM_INF), 0.0);
  }
  EXPECT_NE(a.poses[0].Center(), c.poses[0].Center());
}

}  // namespace
}  // namespace varsfm
