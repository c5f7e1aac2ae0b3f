#include "varsfm/io/bundler.h"

#include <gtest/gtest.h>

#include <fstream>
#include <memory>
#include <sstream>

#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include "io/synthetic_model.h"
#include "support/test_data.h"

namespace varsfm {
namespace {

// Bundler's projection (its manual, section "Output format"): P = R X + t, p = -P / P.z,
// p' = f (1 + k1 |p|^2 + k2 |p|^4) p, in pixels from the image centre with y up.
Eigen::Vector2d BundlerProject(double f, double k1, double k2, const Eigen::Matrix3d& R,
                               const Eigen::Vector3d& t, const Eigen::Vector3d& X) {
  const Eigen::Vector3d P = R * X + t;
  const Eigen::Vector2d p = -P.head<2>() / P.z();
  const double r2 = p.squaredNorm();
  return f * (1.0 + k1 * r2 + k2 * r2 * r2) * p;
}

TEST(Bundler, FileStructureAndProjectionConvention) {
  SyntheticOptions o;
  o.num_images = 4;
  o.num_points = 150;
  o.focal_start = 800;
  o.focal_end = 1100;
  o.k1 = -0.04;
  o.k2 = 0.01;
  Reconstruction rec = testing::ModelFromSynthetic(GenerateSyntheticScene(o));
  rec.DeRegisterImage(4);
  testing::TempDir tmp("bundler");
  WriteBundler(rec, tmp.path() / "bundle.out", tmp.path() / "list.txt");

  std::ifstream list(tmp.path() / "list.txt");
  std::vector<std::string> names;
  for (std::string line; std::getline(list, line);) names.push_back(line);
  EXPECT_EQ(names,
            (std::vector<std::string>{"image0.jpg", "image1.jpg", "image2.jpg", "image3.jpg"}));

  std::ifstream in(tmp.path() / "bundle.out");
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "# Bundle file v0.3");
  size_t num_cameras, num_points;
  in >> num_cameras >> num_points;
  ASSERT_EQ(num_cameras, 4u);
  ASSERT_EQ(num_points, rec.points3D().size());
  struct BundlerCamera {
    double f, k1, k2;
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
  };
  std::vector<BundlerCamera> cameras(num_cameras);
  for (auto& c : cameras) {
    in >> c.f >> c.k1 >> c.k2;
    for (int r = 0; r < 3; ++r) in >> c.R(r, 0) >> c.R(r, 1) >> c.R(r, 2);
    in >> c.t.x() >> c.t.y() >> c.t.z();
  }
  ASSERT_TRUE(in);
  EXPECT_EQ(cameras[3].f, 0.0);  // the unregistered image: Bundler's empty camera
  EXPECT_TRUE(cameras[3].R.isZero());
  EXPECT_DOUBLE_EQ(cameras[1].f, rec.camera(2).focal());
  EXPECT_DOUBLE_EQ(cameras[1].k1, -0.04);

  // Every view reprojects through Bundler's convention onto its stored keypoint, which is the
  // varsfm observation moved to the image centre with y flipped.
  size_t num_views_checked = 0;
  for (const auto& [id, point] : rec.points3D()) {
    Eigen::Vector3d X;
    int r, g, b;
    size_t num_views;
    in >> X.x() >> X.y() >> X.z() >> r >> g >> b >> num_views;
    ASSERT_TRUE(in);
    EXPECT_EQ(X, point.xyz);
    EXPECT_EQ(r, point.color[0]);
    ASSERT_EQ(num_views, point.track.size());
    for (size_t v = 0; v < num_views; ++v) {
      int camera, key;
      Eigen::Vector2d xy;
      in >> camera >> key >> xy.x() >> xy.y();
      const TrackElement& el = point.track[v];
      EXPECT_EQ(camera + 1, static_cast<int>(el.image_id));  // ids 1.. -> indices 0..
      EXPECT_EQ(key, static_cast<int>(el.point2D_idx));
      const Camera& cam = rec.CameraOf(el.image_id);
      const Eigen::Vector2d pixel = rec.image(el.image_id).points2D[el.point2D_idx].xy;
      EXPECT_NEAR(xy.x(), pixel.x() - 0.5 * cam.width, 1e-9);
      EXPECT_NEAR(xy.y(), 0.5 * cam.height - pixel.y(), 1e-9);
      const auto& c = cameras[camera];
      const Eigen::Vector2d projected = BundlerProject(c.f, c.k1, c.k2, c.R, c.t, X);
      // Noise-free synthetic observations at the principal point offset 0: exact up to rounding.
      EXPECT_LT((projected - xy).norm(), 1e-6);
      ++num_views_checked;
    }
  }
  EXPECT_EQ(num_views_checked, rec.NumObservations());
}

// The message about what Bundler's format cannot hold names bundle.out, not the temporary file
// it is written to first.
TEST(Bundler, ApproximationMessageNamesTheFinalFile) {
  SyntheticOptions o;
  o.num_images = 3;
  o.num_points = 50;
  Reconstruction rec = testing::ModelFromSynthetic(GenerateSyntheticScene(o));
  const camera_t camera_id = rec.image(1).camera_id;
  rec.camera(camera_id).params[Camera::kU0] += 10;  // a principal point Bundler cannot hold

  std::ostringstream log;
  const auto previous = spdlog::default_logger();
  spdlog::set_default_logger(std::make_shared<spdlog::logger>(
      "capture", std::make_shared<spdlog::sinks::ostream_sink_st>(log)));
  testing::TempDir tmp("bundler_warning");
  WriteBundler(rec, tmp.path() / "bundle.out", tmp.path() / "list.txt");
  spdlog::set_default_logger(previous);

  EXPECT_NE(log.str().find((tmp.path() / "bundle.out").string() + ": 1 cameras"), std::string::npos)
      << log.str();
  EXPECT_EQ(log.str().find(".tmp"), std::string::npos) << log.str();
}

}  // namespace
}  // namespace varsfm
