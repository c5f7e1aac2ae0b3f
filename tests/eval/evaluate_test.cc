#include "varsfm/eval/evaluate.h"

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "io/synthetic_model.h"
#include "support/test_data.h"
#include "varsfm/io/colmap_model.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;

// Ground truth from a synthetic scene (names as in ModelFromSynthetic), and the
// "estimated" model: the same scene expressed in another frame, gt = sim * estimated.
struct Fixture {
  GroundTruth gt;
  Reconstruction estimated;
  Sim3d sim;
};

Fixture MakeFixture(int num_images = 8) {
  SyntheticOptions o;
  o.num_images = num_images;
  o.num_points = 200;
  o.focal_start = 900;
  o.focal_end = 1400;
  o.principal_point_offset = 15;
  const SyntheticScene scene = GenerateSyntheticScene(o);
  Fixture f;
  for (int i = 0; i < scene.NumImages(); ++i) {
    GroundTruthCamera c;
    c.name = fmt::format("image{}.jpg", i);
    c.camera = scene.cameras[i];
    c.cam_from_world = scene.poses[i];
    f.gt.cameras[c.name] = c;
  }
  f.sim.scale = 0.37;
  f.sim.rotation = Eigen::AngleAxisd(2.0, Eigen::Vector3d(0.3, 1, -0.2).normalized()).matrix();
  f.sim.translation = Eigen::Vector3d(-4, 12, 0.5);
  // X_est = inv(sim) X_gt; a camera x = R X_gt + t becomes x / s' = R A^T X_est + t' (the
  // scale ambiguity of a reconstruction): R_est = R A, t_est = (t + R tr) / s with A, tr, s of sim.
  Reconstruction rec = testing::ModelFromSynthetic(scene);
  const Sim3d inv = f.sim.Inverse();
  for (const image_t id : rec.RegisteredImageIds()) {
    Rigid3d& pose = rec.image(id).cam_from_world;
    const Eigen::Matrix3d R = pose.R();
    pose = Rigid3d(Eigen::Matrix3d(R * f.sim.rotation),
                   (pose.translation + R * f.sim.translation) / f.sim.scale);
  }
  for (auto& [id, point] : rec.points3D()) point.xyz = inv * point.xyz;
  f.estimated = std::move(rec);
  return f;
}

TEST(Evaluate, ExactModelInAnotherFrameHasZeroError) {
  const Fixture f = MakeFixture();
  ASSERT_LT(f.estimated.RmsReprojectionError(), 1e-9);  // the transformed model is exact
  const EvaluationReport r = EvaluateAgainstGroundTruth(f.estimated, f.gt);
  EXPECT_EQ(r.num_gt_images, 8u);
  EXPECT_EQ(r.num_registered, 8u);
  ASSERT_TRUE(r.aligned);
  EXPECT_NEAR(r.alignment.scale, f.sim.scale, 1e-12);
  EXPECT_LT(r.center_error.max, 1e-12);
  EXPECT_LT(r.rotation_error_deg.max, 1e-6);
  EXPECT_LT(r.focal_error_percent.max, 1e-12);
  EXPECT_LT(r.principal_point_error_px.max, 1e-12);
  EXPECT_LT(r.aspect_error.max, 1e-12);
  EXPECT_LT(r.rms_reprojection_error_px, 1e-9);
  EXPECT_EQ(r.num_points3D, f.estimated.points3D().size());
}

TEST(Evaluate, OneCameraMovedOneCentimetre) {
  Fixture f = MakeFixture();
  // Move camera 3's centre by 1 cm in GT units, i.e. 0.01 / s in the estimated frame.
  Image& image = f.estimated.image(3);
  const Eigen::Vector3d moved = image.Center() + Eigen::Vector3d(0, 0.01 / f.sim.scale, 0);
  image.cam_from_world.translation = -(image.cam_from_world.rotation * moved);
  // Robust alignment leaves the moved camera (row 2, "image2.jpg") out: its error is exactly
  // 1 cm, every other camera's 0.
  const EvaluationReport robust =
      EvaluateAgainstGroundTruth(f.estimated, f.gt, {.alignment = {.inlier_threshold = 1e-3}});
  ASSERT_TRUE(robust.aligned);
  EXPECT_EQ(robust.num_alignment_inliers, 7u);
  EXPECT_FALSE(robust.images[2].alignment_inlier);
  EXPECT_NEAR(robust.images[2].center_error, 0.01, 1e-12);
  EXPECT_NEAR(robust.center_error.max, 0.01, 1e-12);
  EXPECT_NEAR(robust.center_error.median, 0.0, 1e-12);
  EXPECT_NEAR(robust.center_error.mean, 0.01 / 8, 1e-12);
  EXPECT_LT(robust.rotation_error_deg.max, 1e-6);
  // Least squares spreads the displacement over all cameras. The true similarity leaves a
  // residual of exactly 1 cm in total, so the least-squares residuals can only be smaller, and
  // the moved camera keeps the largest share.
  const EvaluationReport plain = EvaluateAgainstGroundTruth(f.estimated, f.gt);
  double sum_sq = 0;
  for (const auto& e : plain.images) sum_sq += e.center_error * e.center_error;
  EXPECT_LT(std::sqrt(sum_sq), 0.01);
  EXPECT_EQ(plain.center_error.max, plain.images[2].center_error);
  EXPECT_GT(plain.images[2].center_error, 0.005);
}

TEST(Evaluate, IntrinsicsErrors) {
  Fixture f = MakeFixture();
  f.estimated.camera(2).focal() *= 1.02;  // +2 %
  f.estimated.camera(5).params[Camera::kU0] += 3;
  f.estimated.camera(5).params[Camera::kV0] -= 4;  // 5 px
  f.estimated.camera(6).params[Camera::kAspect] = 1.01;
  const EvaluationReport r = EvaluateAgainstGroundTruth(f.estimated, f.gt);
  EXPECT_NEAR(r.images[1].focal_error_percent, 2.0, 1e-9);
  EXPECT_NEAR(r.focal_error_percent.max, 2.0, 1e-9);
  EXPECT_NEAR(r.focal_error_percent.mean, 2.0 / 8, 1e-9);
  EXPECT_NEAR(r.images[4].principal_point_error_px, 5.0, 1e-9);
  EXPECT_NEAR(r.aspect_error.max, 0.01, 1e-12);
  // Intrinsics do not enter the alignment: centres and rotations stay exact.
  EXPECT_LT(r.center_error.max, 1e-12);
}

TEST(Evaluate, IntrinsicsAtAnotherImageSizeAreScaled) {
  Fixture f = MakeFixture(4);
  for (const auto& [id, cam] : f.estimated.cameras()) {
    Camera& c = f.estimated.camera(id);
    c.width /= 2;  // a model computed on half-size images
    c.height /= 2;
    c.focal() /= 2;
    c.params[Camera::kU0] /= 2;
    c.params[Camera::kV0] /= 2;
  }
  const EvaluationReport r = EvaluateAgainstGroundTruth(f.estimated, f.gt);
  EXPECT_LT(r.focal_error_percent.max, 1e-12);
  EXPECT_LT(r.principal_point_error_px.max, 1e-9);
}

// A photo cropped to 60 % of its width: its principal point and field of view are no longer the
// ground truth's, so its intrinsics are not compared (its pose still is).
TEST(Evaluate, IntrinsicsOfACroppedPhotoAreNotCompared) {
  Fixture f = MakeFixture(4);
  Camera& c = f.estimated.camera(2);
  c.width = static_cast<int>(0.6 * c.width);
  c.params[Camera::kU0] -= 0.2 * f.gt.cameras.begin()->second.camera.width;
  const EvaluationReport r = EvaluateAgainstGroundTruth(f.estimated, f.gt);
  EXPECT_FALSE(r.images[1].intrinsics_compared);
  EXPECT_TRUE(std::isnan(r.images[1].focal_error_percent));
  EXPECT_TRUE(std::isnan(r.images[1].principal_point_error_px));
  EXPECT_EQ(r.focal_error_percent.count, 3u);
  EXPECT_LT(r.focal_error_percent.max, 1e-12);
  EXPECT_LT(r.images[1].center_error, 1e-9);
  EXPECT_NE(FormatReport(r).find("intrinsics of 1 image(s) not compared"), std::string::npos);
  // Resized by half with the height rounded a pixel down (768 -> 383 px): still compared.
  Fixture g = MakeFixture(4);
  Camera& d = g.estimated.camera(2);
  const double s = 0.5;
  d.width = static_cast<int>(d.width * s);
  d.height = static_cast<int>(d.height * s) - 1;
  EXPECT_TRUE(EvaluateAgainstGroundTruth(g.estimated, g.gt).images[1].intrinsics_compared);
}

TEST(Evaluate, UnregisteredAndMissingImages) {
  Fixture f = MakeFixture(5);
  f.estimated.DeRegisterImage(2);
  const EvaluationReport r = EvaluateAgainstGroundTruth(f.estimated, f.gt);
  EXPECT_EQ(r.num_registered, 4u);
  EXPECT_FALSE(r.images[1].registered);
  EXPECT_TRUE(std::isnan(r.images[1].center_error));
  EXPECT_EQ(r.center_error.count, 4u);
  const nlohmann::json j = ToJson(r);
  EXPECT_EQ(j["num_registered"], 4);
  EXPECT_TRUE(j["images"][1]["center_error_m"].is_null());
  EXPECT_NE(FormatReport(r).find("unregistered"), std::string::npos);
  // Two registered images cannot fix a similarity: reported, not aligned.
  f.estimated.DeRegisterImage(1);
  f.estimated.DeRegisterImage(3);
  const EvaluationReport two = EvaluateAgainstGroundTruth(f.estimated, f.gt);
  EXPECT_EQ(two.num_registered, 2u);
  EXPECT_FALSE(two.aligned);
  EXPECT_EQ(two.center_error.count, 0u);
  EXPECT_EQ(two.focal_error_percent.count, 2u);
}

// Photos in subfolders or converted to another format (an iPhone's HEIC against ground truth
// made for JPEGs) pair by file name, then by name without extension, where that is unambiguous.
TEST(Evaluate, ImagesPairByFileNameThenByStem) {
  Fixture f = MakeFixture(5);
  const std::vector<image_t> ids = f.estimated.RegisteredImageIds();
  f.estimated.image(ids[0]).name = "phone/image0.jpg";
  f.estimated.image(ids[1]).name = "image1.HEIC";
  f.estimated.image(ids[2]).name = "sub/image2.dng";
  EXPECT_EQ(EvaluateAgainstGroundTruth(f.estimated, f.gt).num_registered, 5u);
  // Two photos of one stem: neither pairs by it.
  f.estimated.image(ids[3]).name = "image1.png";
  const EvaluationReport r = EvaluateAgainstGroundTruth(f.estimated, f.gt);
  EXPECT_EQ(r.num_registered, 3u);
  EXPECT_FALSE(r.images[1].registered);
}

// Writes ground truth in Strecha's format (K with (0, 0) at a pixel centre, R camera-to-world).
void WriteStrechaFiles(const GroundTruth& gt, const fs::path& dir) {
  fs::create_directories(dir);
  for (const auto& [name, c] : gt.cameras) {
    Eigen::Matrix3d K = c.camera.K();
    K(0, 2) -= 0.5;
    K(1, 2) -= 0.5;
    const Eigen::Matrix3d R = c.cam_from_world.R().transpose();
    const Eigen::Vector3d C = c.Center();
    std::ofstream out(dir / (name + ".camera"));
    for (int r = 0; r < 3; ++r) out << fmt::format("{} {} {}\n", K(r, 0), K(r, 1), K(r, 2));
    out << "0 0 0\n";
    for (int r = 0; r < 3; ++r) out << fmt::format("{} {} {}\n", R(r, 0), R(r, 1), R(r, 2));
    out << fmt::format("{} {} {}\n{} {}\n", C.x(), C.y(), C.z(), c.camera.width, c.camera.height);
  }
}

TEST(Evaluate, GroundTruthFilesRoundTripThroughTheReader) {
  const Fixture f = MakeFixture(4);
  testing::TempDir tmp("eval_gt_files");
  WriteStrechaFiles(f.gt, tmp.path());
  const EvaluationReport r =
      EvaluateAgainstGroundTruth(f.estimated, ReadStrechaGroundTruth(tmp.path()));
  EXPECT_EQ(r.num_registered, 4u);
  EXPECT_LT(r.center_error.max, 1e-9);
  EXPECT_LT(r.principal_point_error_px.max, 1e-9);
}

TEST(Evaluate, CommandLine) {
  const fs::path varsfm = testing::VarsfmBinary();
  if (!fs::exists(varsfm)) GTEST_SKIP() << varsfm << " is not built; skipping";
  const Fixture f = MakeFixture(4);
  testing::TempDir tmp("eval_cli");
  WriteStrechaFiles(f.gt, tmp.path() / "gt");
  WriteColmapModel(f.estimated, tmp.path() / "model", {.binary = true});
  std::string output;
  ASSERT_EQ(
      testing::RunCommand(fmt::format("{} evaluate {} --gt {} --json {}", varsfm.string(),
                                      (tmp.path() / "model").string(), (tmp.path() / "gt").string(),
                                      (tmp.path() / "report.json").string()),
                          &output),
      0)
      << output;
  EXPECT_NE(output.find("registered: 4 / 4"), std::string::npos) << output;
  const nlohmann::json j = nlohmann::json::parse(std::ifstream(tmp.path() / "report.json"));
  EXPECT_EQ(j["num_registered"], 4);
  EXPECT_LT(j["center_error_m"]["max"].get<double>(), 1e-9);
  // A missing folder: exit code 1 and one line naming it.
  EXPECT_EQ(
      testing::RunCommand(fmt::format("{} evaluate {} --gt {}", varsfm.string(),
                                      (tmp.path() / "nope").string(), (tmp.path() / "gt").string()),
                          &output),
      1);
  EXPECT_NE(output.find("nope: model folder does not exist"), std::string::npos) << output;
  EXPECT_EQ(std::count(output.begin(), output.end(), '\n'), 1) << output;
  // Ground truth of other images (none of the model's names): an error, not an empty report.
  fs::create_directories(tmp.path() / "other_gt");
  for (const fs::directory_entry& file : fs::directory_iterator(tmp.path() / "gt"))
    fs::copy_file(file.path(), tmp.path() / "other_gt" / ("x" + file.path().filename().string()));
  EXPECT_EQ(testing::RunCommand(
                fmt::format("{} evaluate {} --gt {}", varsfm.string(),
                            (tmp.path() / "model").string(), (tmp.path() / "other_gt").string()),
                &output),
            1);
  EXPECT_NE(output.find("has a camera in the ground truth"), std::string::npos) << output;
  EXPECT_EQ(std::count(output.begin(), output.end(), '\n'), 1) << output;
}

}  // namespace
}  // namespace varsfm
