#include "varsfm/eval/ground_truth.h"

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <fstream>

#include "support/test_data.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;

TEST(GroundTruth, ConvertsStrechaConventions) {
  testing::TempDir tmp("gt_convert");
  // K with (0, 0) at a pixel centre, R camera-to-world (a 90 degree turn about z), C.
  std::ofstream(tmp.path() / "x.jpg.camera") << "900 0 500\n0 910 330\n0 0 1\n0 0 0\n"
                                                "0 -1 0\n1 0 0\n0 0 1\n"
                                                "1 2 3\n1024 683\n";
  const GroundTruthCamera gt = ReadStrechaCamera(tmp.path() / "x.jpg.camera");
  EXPECT_EQ(gt.name, "x.jpg");
  EXPECT_EQ(gt.camera.width, 1024);
  EXPECT_EQ(gt.camera.height, 683);
  EXPECT_DOUBLE_EQ(gt.camera.focal(), 900);
  EXPECT_DOUBLE_EQ(gt.camera.fy(), 910);
  EXPECT_DOUBLE_EQ(gt.camera.params[Camera::kU0], 500.5);  // + half a pixel
  EXPECT_DOUBLE_EQ(gt.camera.params[Camera::kV0], 330.5);
  EXPECT_LT((gt.Center() - Eigen::Vector3d(1, 2, 3)).norm(), 1e-15);
  // A world point projected by the README's formula K R^T (X - C) and by varsfm's camera and
  // pose: the same pixel, shifted by the half pixel between the two conventions.
  Eigen::Matrix3d R_c2w;
  R_c2w << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  Eigen::Matrix3d K;
  K << 900, 0, 500, 0, 910, 330, 0, 0, 1;
  const Eigen::Vector3d X(1.3, 2.2, 8);
  const Eigen::Vector3d h = K * R_c2w.transpose() * (X - Eigen::Vector3d(1, 2, 3));
  const Eigen::Vector2d strecha = h.head<2>() / h.z();
  const Eigen::Vector2d ours = gt.camera.Project(gt.cam_from_world * X);
  EXPECT_LT((ours - (strecha + Eigen::Vector2d(0.5, 0.5))).norm(), 1e-12);
}

TEST(GroundTruth, BadFilesThrowOneLineNamingTheFile) {
  testing::TempDir tmp("gt_bad");
  EXPECT_THROW(ReadStrechaGroundTruth(tmp.path() / "absent"), Error);
  EXPECT_THROW(ReadStrechaGroundTruth(tmp.path()), Error);  // no .camera files
  std::ofstream(tmp.path() / "short.camera") << "900 0 500\n0 910 330\n";
  try {
    ReadStrechaGroundTruth(tmp.path());
    FAIL() << "expected varsfm::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("short.camera"), std::string::npos) << e.what();
  }
  std::ofstream(tmp.path() / "short.camera")
      << "900 0 500\n0 910 330\n0 0 1\n0 0 0\n1 1 0\n0 1 0\n0 0 1\n0 0 0\n10 10\n";
  EXPECT_THROW(ReadStrechaGroundTruth(tmp.path()), Error);  // R is not a rotation
}

TEST(GroundTruth, ImplausibleImageSizeIsAnError) {
  // A width of 1e20 was converted to int (undefined behaviour) and the camera accepted.
  testing::TempDir tmp("gt_size");
  for (const char* size : {"1e20 2048", "3072 -1", "0 0"}) {
    std::ofstream(tmp.path() / "0000.jpg.camera")
        << "900 0 500\n0 910 330\n0 0 1\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0 0 0\n"
        << size << "\n";
    try {
      ReadStrechaCamera(tmp.path() / "0000.jpg.camera");
      FAIL() << "no error for " << size;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("is not plausible"), std::string::npos) << e.what();
    }
  }
}

TEST(GroundTruth, StrechaFountainIsConsistent) {
  VARSFM_REQUIRE_SHARED_DATA(gt_dir, "strecha/fountain-P11/gt");
  const GroundTruth gt = ReadStrechaGroundTruth(gt_dir);
  ASSERT_EQ(gt.cameras.size(), 11u);
  for (const auto& [name, c] : gt.cameras) {
    EXPECT_EQ(c.camera.width, 1024) << name;
    EXPECT_EQ(c.camera.height, 683) << name;
    // Downscaled 3072x2048 images of a ~35 mm lens: f ~ 920 px, principal point near the centre.
    EXPECT_GT(c.camera.focal(), 800) << name;
    EXPECT_LT(c.camera.focal(), 1050) << name;
    EXPECT_NEAR(c.camera.params[Camera::kAspect], 1.0, 0.01) << name;
    EXPECT_NEAR(c.camera.params[Camera::kU0], 512, 30) << name;
    EXPECT_NEAR(c.camera.params[Camera::kV0], 341.5, 30) << name;
    const Eigen::Matrix3d R = c.cam_from_world.R();
    EXPECT_LT((R * R.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12) << name;
    EXPECT_NEAR(R.determinant(), 1.0, 1e-12) << name;
  }
  // The cameras all look at the fountain: the point nearest to the optical axes of the first
  // and last camera lies in front of both and projects inside both images.
  const GroundTruthCamera& a = gt.cameras.at("0000.jpg");
  const GroundTruthCamera& b = gt.cameras.at("0010.jpg");
  const Eigen::Vector3d da = a.cam_from_world.R().row(2), db = b.cam_from_world.R().row(2);
  const Eigen::Vector3d w = a.Center() - b.Center();
  const double p = da.dot(db), d = da.dot(w), e = db.dot(w);
  const double sa = (p * e - d) / (1 - p * p), sb = (e - p * d) / (1 - p * p);
  EXPECT_GT(sa, 1.0);
  EXPECT_GT(sb, 1.0);
  const Eigen::Vector3d X = 0.5 * (a.Center() + sa * da + b.Center() + sb * db);
  EXPECT_LT(((a.Center() + sa * da) - (b.Center() + sb * db)).norm(), 2.0);  // axes nearly meet
  for (const GroundTruthCamera* c : {&a, &b}) {
    const Eigen::Vector2d pixel = c->camera.Project(c->cam_from_world * X);
    EXPECT_GT(pixel.x(), 0);
    EXPECT_LT(pixel.x(), c->camera.width);
    EXPECT_GT(pixel.y(), 0);
    EXPECT_LT(pixel.y(), c->camera.height);
  }
}

}  // namespace
}  // namespace varsfm
