// The whole sparse chain on real photos of several sizes in one set (another phone, resized or
// rotated copies): each photo's focal length must follow its size, and its principal point stay
// near its own centre, as if the photos had one size.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <string>

#include <fmt/format.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "support/test_data.h"
#include "varsfm/io/colmap_model.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;
using testing::RunCommand;
using testing::ShellQuote;
using testing::TempDir;
using testing::VarsfmBinary;

// The camera of every registered image of OUT/sparse/0, by image name.
std::map<std::string, Camera> CamerasByName(const fs::path& out) {
  const Reconstruction rec = ReadColmapModel(out / "sparse" / "0");
  std::map<std::string, Camera> cameras;
  for (const auto& [id, image] : rec.images())
    if (image.registered) cameras[image.name] = rec.camera(image.camera_id);
  return cameras;
}

void RunSparse(const fs::path& images, const fs::path& out, const std::string& args = "") {
  std::string log;
  ASSERT_EQ(RunCommand(fmt::format("{} run {} {} --until sparse {}", ShellQuote(VarsfmBinary()),
                                   ShellQuote(images), ShellQuote(out), args),
                       &log),
            0)
      << log;
}

TEST(RunCommand, PhotosOfSeveralSizesGetTheirOwnIntrinsics) {
  VARSFM_REQUIRE_SHARED_DATA(et, "bundler/ET");
  TempDir tmp("mixed_sizes");
  const fs::path mixed = tmp.path() / "mixed";
  fs::create_directories(mixed);
  // Every third photo turned to portrait, the others resized by 0.5 .. 0.8: five sizes.
  std::map<std::string, double> scale;
  for (int i = 0; i < 9; ++i) {
    const std::string name = fmt::format("et{:03d}.jpg", i);
    cv::Mat image = cv::imread((et / name).string(), cv::IMREAD_COLOR);
    ASSERT_FALSE(image.empty()) << name;
    scale[name] = i % 3 == 0 ? 1.0 : 0.5 + 0.1 * (i % 4);
    if (i % 3 == 0)
      cv::rotate(image, image, cv::ROTATE_90_CLOCKWISE);
    else
      cv::resize(image, image, cv::Size(), scale[name], scale[name], cv::INTER_AREA);
    ASSERT_TRUE(cv::imwrite((mixed / name).string(), image)) << name;
  }
  RunSparse(et, tmp.path() / "original");
  const auto original = CamerasByName(tmp.path() / "original");
  // Per-image intrinsics (the default); the focal length per image and the rest per size, where
  // a size of one or two photos forms no group; one camera per size (`--intrinsics shared`:
  // photos of another size cannot share one).
  for (const std::string args : {"", "--intrinsics focal-per-image", "--intrinsics shared"}) {
    SCOPED_TRACE(args);
    const fs::path out = tmp.path() / (args.empty() ? "default" : args.substr(13));
    RunSparse(mixed, out, args);
    const auto estimated = CamerasByName(out);
    EXPECT_EQ(estimated.size(), 9u);
    std::set<camera_t> cameras;
    for (const auto& [name, camera] : estimated) {
      ASSERT_TRUE(original.count(name)) << name;
      EXPECT_NEAR(camera.focal() / (original.at(name).focal() * scale.at(name)), 1.0, 0.03) << name;
      const double side = std::max(camera.width, camera.height);
      EXPECT_NEAR(camera.params[Camera::kU0], 0.5 * camera.width, 0.02 * side) << name;
      EXPECT_NEAR(camera.params[Camera::kV0], 0.5 * camera.height, 0.02 * side) << name;
      cameras.insert(camera.camera_id);
    }
    EXPECT_EQ(cameras.size(), args == "--intrinsics shared" ? 5u : 9u)
        << "cameras: one per image or per size";
  }
}

// Every third photo of fountain-P11 cut to its bottom-right 524x383 (a corner cut out in an
// editor): their principal point lies 55 % of the larger side from their centre. Held at the
// centre when they registered, these photos left the model 1.67 m and 15.6 deg off with 10 of
// 11 registered; now 0.59 cm and 0.088 deg (the same crops saved at JPEG quality 92 before: 2.2 cm
// and 0.21 deg; mixed with upscaled photos, 36 cm and 4.9 deg:
// bench/results/2026-12-06-s31-mixed-cameras.md).
TEST(RunCommand, PhotosCroppedOffCentreKeepTheModelAccurate) {
  VARSFM_REQUIRE_SHARED_DATA(fountain, "strecha/fountain-P11");
  TempDir tmp("cropped_off_centre");
  const fs::path cropped = tmp.path() / "cropped";
  fs::create_directories(cropped);
  for (int i = 0; i < 11; ++i) {
    const std::string name = fmt::format("{:04d}.jpg", i);
    cv::Mat image = cv::imread((fountain / "images" / name).string(), cv::IMREAD_COLOR);
    ASSERT_FALSE(image.empty()) << name;
    if (i % 3 == 2) image = image(cv::Rect(500, 300, image.cols - 500, image.rows - 300)).clone();
    ASSERT_TRUE(cv::imwrite((cropped / name).string(), image)) << name;
  }
  RunSparse(cropped, tmp.path() / "out");
  const nlohmann::json e = testing::EvaluateCommand(tmp.path() / "out" / "sparse", fountain / "gt",
                                                    tmp.path() / "eval.json");
  EXPECT_EQ(e["num_registered"], 11);
  // `evaluate` leaves out the crops' intrinsics (their aspect ratio is not the truth's); their
  // principal point must be their own.
  EXPECT_LE(e["center_error_m"]["mean"].get<double>(), 0.010);
  EXPECT_LE(e["rotation_error_deg"]["mean"].get<double>(), 0.15);
  for (const auto& [name, camera] : CamerasByName(tmp.path() / "out")) {
    if (camera.width != 524) continue;
    EXPECT_NEAR(camera.params[Camera::kU0], 506.6 - 500, 10) << name;  // truth (6.6, 35.4) px
    EXPECT_NEAR(camera.params[Camera::kV0], 335.4 - 300, 10) << name;
  }
}

}  // namespace
}  // namespace varsfm
