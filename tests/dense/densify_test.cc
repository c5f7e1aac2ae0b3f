#include "varsfm/dense/densify.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "varsfm/synthetic/rendered_scene.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

// The faces of RenderSyntheticScene's room and boxes (synthetic/rendered_scene.cc, MakeScene):
// origin + s u + t v, s, t in [0, 1].
struct Quad {
  Eigen::Vector3d o, u, v;
};

std::vector<Quad> SceneQuads() {
  std::vector<Quad> quads = {{{-2.5, -1.8, 2.0}, {7.0, 0, 0}, {0, 3.0, 0}},
                             {{-2.5, 1.2, -2.0}, {7.0, 0, 0}, {0, 0, 4.0}},
                             {{-2.5, -1.8, -2.0}, {0, 0, 4.0}, {0, 3.0, 0}}};
  const auto box = [&](Eigen::Vector3d c, Eigen::Vector3d half) {
    const Eigen::Vector3d lo = c - half, hi = c + half;
    quads.push_back({lo, {hi.x() - lo.x(), 0, 0}, {0, hi.y() - lo.y(), 0}});
    quads.push_back({lo, {0, 0, hi.z() - lo.z()}, {0, hi.y() - lo.y(), 0}});
    quads.push_back({{hi.x(), lo.y(), lo.z()}, {0, 0, hi.z() - lo.z()}, {0, hi.y() - lo.y(), 0}});
    quads.push_back({lo, {hi.x() - lo.x(), 0, 0}, {0, 0, hi.z() - lo.z()}});
  };
  box({-0.6, 0.7, 0.6}, {0.5, 0.5, 0.5});
  box({0.9, 0.9, 0.1}, {0.35, 0.3, 0.35});
  return quads;
}

// Nearest hit along a ray (t > 0), infinity when none.
double Hit(const std::vector<Quad>& quads, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
           int* which = nullptr) {
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < quads.size(); ++i) {
    const Quad& q = quads[i];
    const Eigen::Vector3d n = q.u.cross(q.v);
    if (std::abs(n.dot(d)) < 1e-12) continue;
    const double t = n.dot(q.o - o) / n.dot(d);
    if (t <= 1e-9 || t >= best) continue;
    const Eigen::Vector3d p = o + t * d - q.o;
    const double s = p.dot(q.u) / q.u.squaredNorm(), r = p.dot(q.v) / q.v.squaredNorm();
    if (s < 0 || s > 1 || r < 0 || r > 1) continue;
    best = t;
    if (which) *which = static_cast<int>(i);
  }
  return best;
}

// Distance from a point to the nearest face plane, and that plane's unit normal.
double PlaneDistance(const std::vector<Quad>& quads, const Eigen::Vector3d& x,
                     Eigen::Vector3d* normal) {
  double best = std::numeric_limits<double>::infinity();
  for (const Quad& q : quads) {
    const Eigen::Vector3d n = q.u.cross(q.v).normalized();
    const double d = std::abs(n.dot(x - q.o));
    if (d < best) best = d, *normal = n;
  }
  return best;
}

// The rendered scene as a sparse model: true cameras, and as 3D points the surface points seen
// through a grid of pixels of every image, with their visible observations.
Reconstruction SparseModel(const RenderedScene& scene, const std::vector<Quad>& quads) {
  Reconstruction rec;
  const int n = static_cast<int>(scene.images.size());
  for (int i = 0; i < n; ++i) {
    rec.AddCamera(scene.cameras[i]);
    Image image;
    image.image_id = i + 1;
    image.camera_id = scene.cameras[i].camera_id;
    image.name = "image" + std::to_string(i);
    image.cam_from_world = scene.poses[i];
    image.registered = true;
    rec.AddImage(image);
  }
  for (int i = 0; i < n; i += 2) {
    const Camera& cam = scene.cameras[i];
    const Eigen::Vector3d c = scene.poses[i].Center();
    for (double y = 8.5; y < cam.height; y += 24)
      for (double x = 8.5; x < cam.width; x += 24) {
        const Eigen::Vector3d dir =
            scene.poses[i].R().transpose() * cam.ImageToNormalized({x, y}).homogeneous();
        const double t = Hit(quads, c, dir);
        if (!std::isfinite(t)) continue;
        const Eigen::Vector3d X = c + t * dir;
        std::vector<TrackElement> track;
        for (int j = 0; j < n; ++j) {
          const Eigen::Vector3d cj = scene.poses[j].Center();
          const Eigen::Vector3d pc = scene.poses[j] * X;
          if (pc.z() <= 0) continue;
          const Eigen::Vector2d px = scene.cameras[j].Project(pc);
          if (px.x() < 0 || px.y() < 0 || px.x() >= cam.width || px.y() >= cam.height) continue;
          if (Hit(quads, cj, X - cj) < 1 - 1e-6) continue;  // occluded
          Image& image = rec.image(j + 1);
          track.push_back({image.image_id, static_cast<point2D_t>(image.points2D.size())});
          image.points2D.push_back({px});
        }
        if (track.size() >= 2) rec.AddPoint3D(X, track);
      }
  }
  return rec;
}

TEST(Densify, RenderedSceneLiesOnTheTrueSurfaces) {
  RenderedSceneOptions options;
  options.num_images = 4;
  options.width = 320;
  options.height = 240;
  options.focal_start = 256;  // the default 640 at 800 px, scaled to 320 px
  options.arc_degrees = 50;
  const RenderedScene scene = RenderSyntheticScene(options);
  const std::vector<Quad> quads = SceneQuads();
  const Reconstruction rec = SparseModel(scene, quads);
  ASSERT_GT(rec.points3D().size(), 100u);

  DensifyStats stats;
  const PointCloud cloud = Densify(
      rec, [&](image_t id) { return scene.images[id - 1]; }, DensifyOptions{}, &stats);
  EXPECT_GE(stats.num_pairs, 2u);
  // Four 320x240 views: tens of thousands of pixels are matched and survive fusion.
  EXPECT_GT(cloud.points.size(), 20000u);
  ASSERT_EQ(cloud.normals.size(), cloud.points.size());
  ASSERT_EQ(cloud.colors.size(), cloud.points.size());

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
