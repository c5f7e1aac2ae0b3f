#include "varsfm/io/colmap_model.h"

#include <gtest/gtest.h>

#include <fstream>
#include <regex>

#include "io/synthetic_model.h"
#include "support/test_data.h"
#include "varsfm/camera/colmap_models.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;
using testing::ModelFromSynthetic;

// Per-image intrinsics covering several COLMAP models: image 1 plain (SIMPLE_PINHOLE), image 2
// with k1 (SIMPLE_RADIAL), image 3 with k1, k2 (RADIAL), image 4 with aspect (OPENCV); a point
// deleted leaves a gap in the ids; image 5 is unregistered and must not be written.
Reconstruction TestModel() {
  SyntheticOptions o;
  o.num_images = 5;
  o.num_points = 300;
  o.focal_start = 900;
  o.focal_end = 1300;
  o.principal_point_offset = 20;
  o.noise_sigma = 0.5;
  SyntheticScene scene = GenerateSyntheticScene(o);
  scene.cameras[1].params[Camera::kK1] = -0.05;
  scene.cameras[2].params[Camera::kK1] = 0.03;
  scene.cameras[2].params[Camera::kK2] = -0.01;
  scene.cameras[3].params[Camera::kAspect] = 1.02;
  scene.cameras[3].params[Camera::kK1] = 0.01;
  Reconstruction rec = ModelFromSynthetic(scene);
  rec.DeletePoint3D(rec.points3D().begin()->first + 3);
  rec.DeRegisterImage(5);
  return rec;
}

// The same model up to point ids (the reader renumbers them): cameras, registered images,
// poses, 2D points, and through each 2D point its 3D point, colour, error and track.
// `xy_tolerance` (px) is for COLMAP's own output, which stores 2D points in float.
void ExpectSameModel(const Reconstruction& a, const Reconstruction& b, double xy_tolerance = 0) {
  ASSERT_EQ(a.cameras().size(), b.cameras().size());
  for (const auto& [id, ca] : a.cameras()) {
    ASSERT_TRUE(b.ExistsCamera(id));
    const Camera& cb = b.camera(id);
    EXPECT_EQ(ca.width, cb.width);
    EXPECT_EQ(ca.height, cb.height);
    for (int p = 0; p < Camera::kNumParams; ++p)
      EXPECT_NEAR(ca.params[p], cb.params[p], 1e-12 * std::max(1.0, std::abs(ca.params[p])))
          << "camera " << id << " param " << p;
  }
  ASSERT_EQ(a.NumRegisteredImages(), b.images().size());
  ASSERT_EQ(a.points3D().size(), b.points3D().size());
  for (const image_t id : a.RegisteredImageIds()) {
    ASSERT_TRUE(b.ExistsImage(id));
    const Image& ia = a.image(id);
    const Image& ib = b.image(id);
    EXPECT_EQ(ia.name, ib.name);
    EXPECT_EQ(ia.camera_id, ib.camera_id);
    EXPECT_TRUE(ib.registered);
    EXPECT_LT((ia.cam_from_world.R() - ib.cam_from_world.R()).norm(), 1e-14);
    EXPECT_LT((ia.cam_from_world.translation - ib.cam_from_world.translation).norm(), 1e-14);
    ASSERT_EQ(ia.points2D.size(), ib.points2D.size());
    for (size_t k = 0; k < ia.points2D.size(); ++k) {
      EXPECT_LE((ia.points2D[k].xy - ib.points2D[k].xy).cwiseAbs().maxCoeff(), xy_tolerance);
      ASSERT_EQ(ia.points2D[k].HasPoint3D(), ib.points2D[k].HasPoint3D());
      if (!ia.points2D[k].HasPoint3D()) continue;
      const Point3D& pa = a.point3D(ia.points2D[k].point3D_id);
      const Point3D& pb = b.point3D(ib.points2D[k].point3D_id);
      EXPECT_EQ(pa.xyz, pb.xyz);
      EXPECT_EQ(pa.color, pb.color);
      EXPECT_EQ(pa.error, pb.error);
      ASSERT_EQ(pa.track.size(), pb.track.size());
      for (size_t t = 0; t < pa.track.size(); ++t) {
        EXPECT_EQ(pa.track[t].image_id, pb.track[t].image_id);
        EXPECT_EQ(pa.track[t].point2D_idx, pb.track[t].point2D_idx);
      }
    }
  }
}

TEST(ColmapModel, TextRoundTripIsExact) {
  const Reconstruction rec = TestModel();
  testing::TempDir tmp("colmap_text");
  WriteColmapModel(rec, tmp.path() / "model", {.binary = false});
  EXPECT_TRUE(fs::exists(tmp.path() / "model" / "images.txt"));
  EXPECT_FALSE(fs::exists(tmp.path() / "model" / "images.bin"));
  ExpectSameModel(rec, ReadColmapModel(tmp.path() / "model"));
}

TEST(ColmapModel, BinaryRoundTripIsExact) {
  const Reconstruction rec = TestModel();
  testing::TempDir tmp("colmap_bin");
  WriteColmapModel(rec, tmp.path() / "model", {.binary = true});
  EXPECT_TRUE(fs::exists(tmp.path() / "model" / "images.bin"));
  ExpectSameModel(rec, ReadColmapModel(tmp.path() / "model"));
}

TEST(ColmapModel, ChoosesSmallestModelUnlessForced) {
  const Reconstruction rec = TestModel();
  testing::TempDir tmp("colmap_models");
  WriteColmapModel(rec, tmp.path() / "smallest");
  WriteColmapModel(rec, tmp.path() / "forced", {.force_model_id = kColmapOpenCV});
  auto models = [](const fs::path& file) {
    std::ifstream in(file);
    std::vector<std::string> names;
    for (std::string line; std::getline(in, line);) {
      if (line.empty() || line[0] == '#') continue;
      std::istringstream s(line);
      std::string id, model;
      s >> id >> model;
      names.push_back(model);
    }
    return names;
  };
  EXPECT_EQ(models(tmp.path() / "smallest" / "cameras.txt"),
            (std::vector<std::string>{"SIMPLE_PINHOLE", "SIMPLE_RADIAL", "RADIAL", "OPENCV",
                                      "SIMPLE_PINHOLE"}));
  EXPECT_EQ(models(tmp.path() / "forced" / "cameras.txt"), std::vector<std::string>(5, "OPENCV"));
  // OPENCV holds every parameter varsfm has, so the forced model reads back the same.
  ExpectSameModel(rec, ReadColmapModel(tmp.path() / "forced"));
}

TEST(ColmapModel, ImagesTextLayout) {
  Reconstruction rec;
  Camera camera = Camera::FromFocal(640, 480, 500);
  camera.camera_id = 7;
  rec.AddCamera(camera);
  Image image;
  image.image_id = 3;
  image.camera_id = 7;
  image.name = "a b.jpg";  // COLMAP allows spaces: the name is the rest of the line
  image.cam_from_world.translation = Eigen::Vector3d(1, 2, 3);
  image.registered = true;
  image.points2D = {{Eigen::Vector2d(10.5, 20.25)}, {Eigen::Vector2d(30, 40)}};
  rec.AddImage(image);
  Image other = image;
  other.image_id = 4;
  other.name = "c.jpg";
  rec.AddImage(other);
  rec.AddPoint3D(Eigen::Vector3d(0, 0, 5), {{3, 1}, {4, 1}});
  testing::TempDir tmp("colmap_layout");
  WriteColmapModel(rec, tmp.path());
  std::ifstream in(tmp.path() / "images.txt");
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);)
    if (line.empty() || line[0] != '#') lines.push_back(line);
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0], "3 1 0 0 0 1 2 3 7 a b.jpg");
  EXPECT_EQ(lines[1], "10.5 20.25 -1 30 40 1");
  EXPECT_EQ(ReadColmapModel(tmp.path()).image(3).name, "a b.jpg");
}

TEST(ColmapModel, FailedWriteLeavesNoModel) {
  Reconstruction rec = TestModel();
  testing::TempDir tmp("colmap_fail");
  // A forced fisheye id is not exportable: the write throws after the folder was started.
  EXPECT_THROW(WriteColmapModel(rec, tmp.path() / "model", {.force_model_id = 5}), Error);
  EXPECT_FALSE(fs::exists(tmp.path() / "model"));
  EXPECT_TRUE(fs::is_empty(tmp.path()));  // no temporary folder left behind either
  // Over an existing model, the old files stay complete.
  WriteColmapModel(rec, tmp.path() / "model");
  EXPECT_THROW(WriteColmapModel(rec, tmp.path() / "model", {.force_model_id = 5}), Error);
  ExpectSameModel(rec, ReadColmapModel(tmp.path() / "model"));
}

// COLMAP's mapper writes its models as sparse/0, sparse/1, ...: a reader given sparse/ reads
// model 0; a folder that holds a model is read itself.
TEST(ColmapModel, ParentOfNumberedModelsReadsModelZero) {
  testing::TempDir tmp("colmap_numbered");
  const Reconstruction rec = TestModel();
  Reconstruction other = TestModel();
  other.DeRegisterImage(4);
  WriteColmapModel(rec, tmp.path() / "sparse" / "0", {.binary = true});
  WriteColmapModel(other, tmp.path() / "sparse" / "1", {.binary = false});
  EXPECT_EQ(ResolveColmapModelFolder(tmp.path() / "sparse"), tmp.path() / "sparse" / "0");
  ExpectSameModel(rec, ReadColmapModel(tmp.path() / "sparse"));
  ExpectSameModel(other, ReadColmapModel(tmp.path() / "sparse" / "1"));
  WriteColmapModel(other, tmp.path() / "sparse", {.binary = true});
  EXPECT_EQ(ResolveColmapModelFolder(tmp.path() / "sparse"), tmp.path() / "sparse");
  ExpectSameModel(other, ReadColmapModel(tmp.path() / "sparse"));
}

TEST(ColmapModel, BadInputThrowsOneLineNamingTheFile) {
  testing::TempDir tmp("colmap_bad");
  EXPECT_THROW(ReadColmapModel(tmp.path() / "absent"), Error);
  EXPECT_THROW(ReadColmapModel(tmp.path()), Error);  // empty folder
  WriteColmapModel(TestModel(), tmp.path());
  std::ofstream(tmp.path() / "cameras.txt") << "1 OPENCV_FISHEYE 640 480 1 2 3 4 5 6 7 8\n";
  try {
    ReadColmapModel(tmp.path());
    FAIL() << "expected varsfm::Error";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("cameras.txt"), std::string::npos) << message;
    EXPECT_NE(message.find("OPENCV_FISHEYE"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  // A truncated binary file.
  WriteColmapModel(TestModel(), tmp.path() / "bin", {.binary = true});
  fs::resize_file(tmp.path() / "bin" / "points3D.bin", 100);
  EXPECT_THROW(ReadColmapModel(tmp.path() / "bin"), Error);
}

// ---- Interoperability with COLMAP 3.8 itself (skipped where colmap is not installed). ----

bool HaveColmap() { return testing::RunCommand("colmap help") == 0; }

// The count after `label: ` in model_analyzer's output, or -1.
long AnalyzerCount(const std::string& output, const std::string& label) {
  std::smatch m;
  if (!std::regex_search(output, m, std::regex(label + ": (\\d+)"))) return -1;
  return std::stol(m[1]);
}

TEST(ColmapModel, ColmapModelAnalyzerAcceptsTextAndBinary) {
  if (!HaveColmap()) GTEST_SKIP() << "colmap is not installed; skipping";
  const Reconstruction rec = TestModel();
  testing::TempDir tmp("colmap_analyzer");
  for (bool binary : {false, true}) {
    const fs::path dir = tmp.path() / (binary ? "bin" : "txt");
    WriteColmapModel(rec, dir, {.binary = binary});
    std::string output;
    ASSERT_EQ(testing::RunCommand("colmap model_analyzer --path " + dir.string(), &output), 0)
        << output;
    EXPECT_EQ(AnalyzerCount(output, "Registered images"), 4) << output;
    EXPECT_EQ(AnalyzerCount(output, "Points"), static_cast<long>(rec.points3D().size())) << output;
    EXPECT_EQ(AnalyzerCount(output, "Observations"), static_cast<long>(rec.NumObservations()))
        << output;
  }
}

TEST(ColmapModel, ReadsColmapModelConverterOutput) {
  if (!HaveColmap()) GTEST_SKIP() << "colmap is not installed; skipping";
  const Reconstruction rec = TestModel();
  testing::TempDir tmp("colmap_converter");
  WriteColmapModel(rec, tmp.path() / "ours", {.binary = false});
  // COLMAP reads our text and writes its own binary and text; both must read back the same.
  for (const char* type : {"BIN", "TXT"}) {
    const fs::path out = tmp.path() / type;
    fs::create_directories(out);
    std::string output;
    ASSERT_EQ(testing::RunCommand("colmap model_converter --input_path " +
                                      (tmp.path() / "ours").string() + " --output_path " +
                                      out.string() + " --output_type " + type,
                                  &output),
              0)
        << output;
    // Float 2D points: 24-bit mantissa, about 1e-4 px at 1000 px.
    ExpectSameModel(rec, ReadColmapModel(out), 1e-4);
  }
}

}  // namespace
}  // namespace varsfm
