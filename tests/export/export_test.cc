#include <fstream>
#include <set>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "export/scene.h"
#include "support/dng_writer.h"
#include "support/heif_writer.h"
#include "support/test_data.h"
#include "varsfm/export/gaussian_splatting.h"
#include "varsfm/export/nerfstudio.h"
#include "varsfm/image/exif.h"
#include "varsfm/image/image_file.h"
#include "varsfm/image/jpeg_check.h"
#include "varsfm/io/colmap_model.h"
#include "varsfm/pipeline/export.h"
#include "varsfm/util/atomic_file.h"
#include "varsfm/util/error.h"
#include "varsfm/util/new_folder.h"
#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

using testing::ZoomingModel;

// The 3DGS layout: PINHOLE cameras that keep each image's focal, photos of the cameras' sizes,
// and every observation where its 3D point projects through the pinhole camera (centred: the
// capture's principal points lie 6 px off).
TEST(GaussianSplattingExport, WritesPinholeModelAndUndistortedPhotos) {
  TempDir tmp("export_3dgs");
  const Reconstruction model = ZoomingModel();
  testing::WritePhotos(model, tmp.path() / "photos");
  const auto summary = ExportGaussianSplatting(model, tmp.path() / "photos", tmp.path() / "gs");
  EXPECT_EQ(summary.num_images, model.NumRegisteredImages());
  EXPECT_EQ(summary.num_centred, model.NumRegisteredImages());
  EXPECT_EQ(summary.num_off_centre, 0u);

  const Reconstruction exported = ReadColmapModel(tmp.path() / "gs" / "sparse" / "0");
  ASSERT_EQ(exported.NumRegisteredImages(), model.NumRegisteredImages());
  std::set<double> focals;
  for (const auto& [id, image] : exported.images()) {
    const Camera& pinhole = exported.CameraOf(id);
    const Camera& original = model.CameraOf(id);
    EXPECT_FALSE(pinhole.HasDistortion());
    EXPECT_NEAR(pinhole.focal(), original.focal(), 1e-9);
    focals.insert(pinhole.focal());
    const cv::Mat photo = ReadImagePixels(tmp.path() / "gs" / "images" / image.name);
    EXPECT_EQ(photo.cols, pinhole.width);
    EXPECT_EQ(photo.rows, pinhole.height);
    for (const Point2D& point : image.points2D) {
      if (!point.HasPoint3D()) continue;
      Eigen::Vector2d projected;
      ASSERT_TRUE(exported.Project(id, exported.point3D(point.point3D_id).xyz, &projected));
      EXPECT_LT((projected - point.xy).norm(), 1e-3);
    }
  }
  EXPECT_EQ(focals.size(), exported.images().size());  // each image its own focal
  // Only the finished folder is left.
  for (const auto& entry : fs::directory_iterator(tmp.path())) {
    EXPECT_TRUE(entry.path().filename() == "photos" || entry.path().filename() == "gs")
        << entry.path();
  }
}

// 3DGS' reference loader ignores cx, cy: each photo is cut around its principal point, which
// then lies at its centre exactly; a photo cropped so far off-centre that centring would leave
// less than half of it keeps its principal point (the COLMAP model is exact) and is counted, so
// that the command can warn; so is every off-centre photo when asked to keep them.
TEST(GaussianSplattingExport, CentresPrincipalPointsAndCountsThoseItCannot) {
  TempDir tmp("export_3dgs_off_centre");
  Reconstruction model = ZoomingModel();
  const std::vector<image_t> ids = model.RegisteredImageIds();
  const image_t shifted = ids[0], cropped = ids[1];
  model.CameraOf(shifted).params[Camera::kU0] -= 0.2 * model.CameraOf(shifted).width;
  model.CameraOf(cropped).params[Camera::kU0] -= 0.4 * model.CameraOf(cropped).width;
  testing::WritePhotos(model, tmp.path() / "photos");

  const auto summary = ExportGaussianSplatting(model, tmp.path() / "photos", tmp.path() / "gs");
  EXPECT_EQ(summary.num_centred, ids.size() - 1);
  EXPECT_EQ(summary.num_off_centre, 1u);
  const Reconstruction exported = ReadColmapModel(tmp.path() / "gs" / "sparse" / "0");
  for (const image_t id : ids) {
    const Camera& pinhole = exported.CameraOf(id);
    if (id == cropped) {
      EXPECT_LT(pinhole.params[Camera::kU0], 0.2 * pinhole.width);
      continue;
    }
    EXPECT_EQ(pinhole.PrincipalPointOffset(), Eigen::Vector2d::Zero()) << id;
    const cv::Mat photo = ReadImagePixels(tmp.path() / "gs" / "images" / exported.image(id).name);
    EXPECT_EQ(photo.cols, pinhole.width);
    EXPECT_EQ(photo.rows, pinhole.height);
  }
  // The shifted photo, centred, is narrower than with its principal point kept.
  const auto kept = ExportGaussianSplatting(model, tmp.path() / "photos", tmp.path() / "kept",
                                            PrincipalPointPlacement::kKept);
  EXPECT_EQ(kept.num_centred, 0u);
  EXPECT_EQ(kept.num_off_centre, 2u);
  const Reconstruction kept_model = ReadColmapModel(tmp.path() / "kept" / "sparse" / "0");
  EXPECT_LT(exported.CameraOf(shifted).width, kept_model.CameraOf(shifted).width);
  EXPECT_LT(kept_model.CameraOf(shifted).params[Camera::kU0],
            0.4 * kept_model.CameraOf(shifted).width);
}

// An iPhone's HEIC photos and a camera's raw files, which neither 3DGS' nor nerfstudio's loader
// opens: exported as JPEG under their name with ".jpg" appended, and the model and
// transforms.json name those files.
TEST(Export, HeicAndRawPhotosAreWrittenAsJpeg) {
  TempDir tmp("export_heic");
  Reconstruction model = ZoomingModel();
  fs::create_directories(tmp.path() / "photos");
  for (const auto& [id, image] : model.images()) {
    const cv::Mat photo = testing::RenderRayPattern(model.CameraOf(id));
    const bool raw = id % 2 == 0;
    model.image(id).name = "IMG_" + std::to_string(id) + (raw ? ".DNG" : ".HEIC");
    const std::vector<uint8_t> bytes = raw ? testing::EncodeDng(photo) : testing::EncodeHeic(photo);
    ASSERT_FALSE(bytes.empty());
    WriteBytesAtomically(tmp.path() / "photos" / model.image(id).name, bytes);
  }
  ExportGaussianSplatting(model, tmp.path() / "photos", tmp.path() / "gs");
  ExportNerfstudio(model, tmp.path() / "photos", tmp.path() / "ns");
  const Reconstruction exported = ReadColmapModel(tmp.path() / "gs" / "sparse" / "0");
  const nlohmann::json transforms =
      nlohmann::json::parse(std::ifstream(tmp.path() / "ns" / "transforms.json"));
  std::set<std::string> frame_files;
  for (const auto& frame : transforms["frames"]) frame_files.insert(frame["file_path"]);
  for (const auto& [id, image] : model.images()) {
    const std::string jpeg_name = image.name + ".jpg";
    EXPECT_EQ(exported.image(id).name, jpeg_name);
    EXPECT_TRUE(frame_files.count("images/" + jpeg_name)) << jpeg_name;
    for (const fs::path& file :
         {tmp.path() / "gs" / "images" / jpeg_name, tmp.path() / "ns" / "images" / jpeg_name}) {
      const std::vector<uint8_t> bytes = ReadImageFile(file);
      EXPECT_TRUE(LooksLikeJpeg(bytes.data(), bytes.size())) << file;
    }
    EXPECT_EQ(ReadImagePixels(tmp.path() / "ns" / "images" / jpeg_name).size(),
              cv::Size(model.CameraOf(id).width, model.CameraOf(id).height));
  }
}

// COLMAP itself reads the exported model (COLMAP is a test dependency; skipped without it).
TEST(GaussianSplattingExport, ColmapReadsTheModel) {
  if (testing::RunCommand("command -v colmap >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "colmap is not installed; skipping";
  }
  TempDir tmp("export_3dgs_colmap");
  const Reconstruction model = ZoomingModel();
  testing::WritePhotos(model, tmp.path() / "photos");
  ExportGaussianSplatting(model, tmp.path() / "photos", tmp.path() / "gs");
  std::string output;
  ASSERT_EQ(testing::RunCommand("colmap model_analyzer --path " +
                                    testing::ShellQuote(tmp.path() / "gs" / "sparse" / "0"),
                                &output),
            0)
      << output;
  EXPECT_NE(output.find("Registered images: " + std::to_string(model.NumRegisteredImages())),
            std::string::npos)
      << output;
}

TEST(GaussianSplattingExport, MissingPhotoFailsWithoutOutput) {
  TempDir tmp("export_3dgs_missing");
  const Reconstruction model = ZoomingModel();
  testing::WritePhotos(model, tmp.path() / "photos");
  fs::remove(tmp.path() / "photos" / model.images().begin()->second.name);
  EXPECT_THROW(ExportGaussianSplatting(model, tmp.path() / "photos", tmp.path() / "gs"), Error);
  EXPECT_FALSE(fs::exists(tmp.path() / "gs"));
}

// nerfstudio's convention: c2w maps the OpenGL camera (x right, y up, looking down -z) into the
// world, and a point projects as u = fl_x x / -z + cx, v = -fl_y y / -z + cy.
TEST(NerfstudioExport, FramesProjectLikeTheModel) {
  SyntheticOptions options = testing::ZoomingDistortedCapture();
  options.k1 = options.k2 = 0;  // compare pinhole projections exactly
  const Reconstruction model = ZoomingModel(options);
  const nlohmann::json transforms = NerfstudioTransforms(model);
  EXPECT_EQ(transforms["camera_model"], "OPENCV");
  ASSERT_EQ(transforms["frames"].size(), model.NumRegisteredImages());
  for (const nlohmann::json& frame : transforms["frames"]) {
    const image_t id = frame["colmap_im_id"];
    const Camera& camera = model.CameraOf(id);
    EXPECT_EQ(frame["file_path"], "images/" + model.image(id).name);
    EXPECT_DOUBLE_EQ(frame["fl_x"].get<double>(), camera.focal());
    EXPECT_DOUBLE_EQ(frame["fl_y"].get<double>(), camera.fy());
    Eigen::Matrix4d c2w;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) c2w(r, c) = frame["transform_matrix"][r][c];
    EXPECT_LT((c2w.topRightCorner<3, 1>() - model.image(id).Center()).norm(), 1e-9);
    const Eigen::Matrix4d w2c = c2w.inverse();
    int checked = 0;
    for (const Point2D& point : model.image(id).points2D) {
      if (!point.HasPoint3D()) continue;
      const Eigen::Vector3d xyz = model.point3D(point.point3D_id).xyz;
      const Eigen::Vector3d p = (w2c * xyz.homogeneous()).head<3>();
      ASSERT_LT(p.z(), 0);
      const Eigen::Vector2d uv(
          frame["fl_x"].get<double>() * p.x() / -p.z() + frame["cx"].get<double>(),
          -frame["fl_y"].get<double>() * p.y() / -p.z() + frame["cy"].get<double>());
      Eigen::Vector2d expected;
      ASSERT_TRUE(model.Project(id, xyz, &expected));
      EXPECT_LT((uv - expected).norm(), 1e-6);
      ++checked;
    }
    EXPECT_GT(checked, 10);
  }
}

TEST(NerfstudioExport, WritesTransformsPhotosAndPoints) {
  TempDir tmp("export_nerfstudio");
  const Reconstruction model = ZoomingModel();
  testing::WritePhotos(model, tmp.path() / "photos");
  ExportNerfstudio(model, tmp.path() / "photos", tmp.path() / "ns");
  const nlohmann::json transforms =
      nlohmann::json::parse(std::ifstream(tmp.path() / "ns" / "transforms.json"));
  for (const nlohmann::json& frame : transforms["frames"]) {
    const image_t id = frame["colmap_im_id"];
    EXPECT_DOUBLE_EQ(frame["k1"].get<double>(), model.CameraOf(id).params[Camera::kK1]);
    EXPECT_TRUE(fs::is_regular_file(tmp.path() / "ns" / frame["file_path"].get<std::string>()));
  }
  EXPECT_TRUE(fs::is_regular_file(tmp.path() / "ns" / "sparse_pc.ply"));
}

// A JPEG stored turned, with the EXIF orientation 6 that turns it upright: the model's camera is
// that of the upright pixels, which nerfstudio's loader does not turn; the export writes it
// upright.
TEST(NerfstudioExport, APhotoStoredTurnedIsWrittenUpright) {
  TempDir tmp("export_nerfstudio_turned");
  Reconstruction model = ZoomingModel();
  const image_t turned = model.images().begin()->first;
  model.image(turned).name = "turned.jpg";
  testing::WritePhotos(model, tmp.path() / "photos");
  const fs::path photo = tmp.path() / "photos" / "turned.jpg";
  const cv::Mat upright = ReadImagePixels(photo);
  cv::Mat stored;
  cv::rotate(upright, stored, cv::ROTATE_90_COUNTERCLOCKWISE);  // orientation 6 turns it back
  WriteImage(photo, stored);
  std::vector<uint8_t> jpeg = ReadImageFile(photo);
  // An APP1 segment after the start-of-image marker: "Exif\0\0", a little-endian TIFF header,
  // IFD0 with the one Orientation entry (0x0112, SHORT, 1 value: 6).
  const std::vector<uint8_t> exif = {'E',  'x',  'i', 'f', 0, 0, 'I', 'I', 42, 0, 8, 0, 0, 0, 1, 0,
                                     0x12, 0x01, 3,   0,   1, 0, 0,   0,   6,  0, 0, 0, 0, 0, 0, 0};
  std::vector<uint8_t> segment = {0xFF, 0xE1, 0, static_cast<uint8_t>(exif.size() + 2)};
  segment.insert(segment.end(), exif.begin(), exif.end());
  jpeg.insert(jpeg.begin() + 2, segment.begin(), segment.end());
  std::ofstream(photo, std::ios::binary)
      .write(reinterpret_cast<const char*>(jpeg.data()), static_cast<std::streamsize>(jpeg.size()));
  ASSERT_EQ(ReadImagePixels(photo).size(), upright.size()) << "the test photo is not tagged";

  ExportNerfstudio(model, tmp.path() / "photos", tmp.path() / "ns");
  const std::vector<uint8_t> written = ReadImageFile(tmp.path() / "ns" / "images" / "turned.jpg");
  EXPECT_EQ(ExifOrientation(written.data(), written.size()), 1);
  const cv::Mat pixels = DecodeImage("turned.jpg", written, ColorMode::kColor);
  ASSERT_EQ(pixels.size(), upright.size());
  EXPECT_LT(cv::norm(pixels, upright, cv::NORM_L1) / upright.total() / 3, 4.0);  // JPEG's loss
  // An upright photo is copied as it is.
  for (const auto& [id, image] : model.images())
    if (id != turned)
      EXPECT_EQ(ReadImageFile(tmp.path() / "photos" / image.name),
                ReadImageFile(tmp.path() / "ns" / "images" / image.name));
}

TEST(ExportOptions, CheckRefusesBadValues) {
  TempDir tmp("export_options");
  ExportOptions options;
  EXPECT_THROW(options.Check(), OptionError);  // no model
  options.model = tmp.path() / "missing";
  options.output = tmp.path() / "out";
  EXPECT_THROW(options.Check(), Error);
  options.model = tmp.path();
  EXPECT_NO_THROW(options.Check());
  options.centre_principal_point = false;  // --keep-principal-point: for 3dgs only
  EXPECT_NO_THROW(options.Check());
  options.format = ExportFormat::kNerfstudio;
  EXPECT_THROW(options.Check(), OptionError);
  options.centre_principal_point = true;
  EXPECT_NO_THROW(options.Check());
  options.image_dir = tmp.path() / "no-photos";
  EXPECT_THROW(options.Check(), Error);
  options.image_dir.clear();
  fs::create_directories(options.output);
  std::ofstream(options.output / "keep.txt") << "x";
  EXPECT_THROW(options.Check(), Error);  // an output that holds files is never touched
  EXPECT_THROW(ParseExportFormat("ply"), Error);
  EXPECT_EQ(ParseExportFormat("nerfstudio"), ExportFormat::kNerfstudio);
}

TEST(WriteNewFolder, FailedWriterLeavesNothing) {
  TempDir tmp("new_folder");
  EXPECT_THROW(WriteNewFolder(tmp.path() / "out",
                              [](const fs::path& dir) {
                                std::ofstream(dir / "half.txt") << "x";
                                Fail("writer failed");
                              }),
               Error);
  EXPECT_TRUE(fs::is_empty(tmp.path()));
}

// The command line, as a user runs it on a model folder written by `map`.
TEST(ExportCommand, WritesBothFormatsAndRefusesAnOccupiedOutput) {
  TempDir tmp("export_cli");
  const Reconstruction model = ZoomingModel();
  testing::WritePhotos(model, tmp.path() / "photos");
  WriteColmapModel(model, tmp.path() / "sparse", {.binary = true});
  const auto q = [](const fs::path& p) { return testing::ShellQuote(p); };
  const std::string base = q(testing::VarsfmBinary()) + " export " + q(tmp.path() / "sparse");
  std::string output;
  ASSERT_EQ(
      testing::RunCommand(
          base + " " + q(tmp.path() / "gs") + " --images " + q(tmp.path() / "photos"), &output),
      0)
      << output;
  EXPECT_TRUE(fs::is_regular_file(tmp.path() / "gs" / "sparse" / "0" / "cameras.bin"));
  // Principal points centred by default (the capture's lie 6 px off), kept on request.
  ASSERT_EQ(testing::RunCommand(base + " " + q(tmp.path() / "gs_kept") + " --images " +
                                    q(tmp.path() / "photos") + " --keep-principal-point",
                                &output),
            0)
      << output;
  for (const auto& [folder, centred] : {std::pair{"gs", true}, std::pair{"gs_kept", false}}) {
    const Reconstruction exported = ReadColmapModel(tmp.path() / folder / "sparse" / "0");
    for (const auto& [id, camera] : exported.cameras())
      EXPECT_EQ(camera.PrincipalPointOffset().isZero(0.0), centred) << folder;
  }
  ASSERT_EQ(testing::RunCommand(base + " " + q(tmp.path() / "ns") +
                                    " --format nerfstudio --images " + q(tmp.path() / "photos"),
                                &output),
            0)
      << output;
  EXPECT_TRUE(fs::is_regular_file(tmp.path() / "ns" / "transforms.json"));
  EXPECT_NE(output.find("export: "), std::string::npos) << output;
  // --quiet: nothing but warnings and errors.
  ASSERT_EQ(testing::RunCommand(q(testing::VarsfmBinary()) + " --quiet export " +
                                    q(tmp.path() / "sparse") + " " + q(tmp.path() / "quiet") +
                                    " --images " + q(tmp.path() / "photos"),
                                &output),
            0)
      << output;
  EXPECT_EQ(output, "");
  // Again into the same folder: refused with one line, the folder untouched.
  EXPECT_NE(testing::RunCommand(base + " " + q(tmp.path() / "ns") +
                                    " --format nerfstudio --images " + q(tmp.path() / "photos"),
                                &output),
            0);
  EXPECT_NE(output.find("--output"), std::string::npos) << output;
  EXPECT_TRUE(fs::is_regular_file(tmp.path() / "ns" / "transforms.json"));
}

}  // namespace
}  // namespace varsfm
