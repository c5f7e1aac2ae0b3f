// End to end through the command-line tool: a sparse model with the synthetic scene's exact
// cameras, its photos and a mesh of its geometry -> `texture` -> `render` and
// `evaluate --render`; and one-line errors for bad input.
#include <gtest/gtest.h>

#include <fstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "support/test_data.h"
#include "synthetic_mesh.h"
#include "varsfm/image/image_file.h"
#include "varsfm/io/colmap_model.h"
#include "varsfm/io/mesh_ply.h"
#include "varsfm/synthetic/rendered_scene.h"

namespace varsfm {
namespace {

using testing::RunCommand;
using testing::ShellQuote;
using testing::TempDir;
using testing::VarsfmBinary;

// OUT/`model`, OUT/images and OUT/mesh.ply for the rendered synthetic scene: the model in
// `map`'s layout (sparse/0) or in a single model folder (sparse), as other tools write it.
void WriteSyntheticInputs(const std::filesystem::path& out, int num_registered,
                          const std::filesystem::path& model = "sparse") {
  RenderedSceneOptions o;
  o.num_images = 4;
  o.width = 320;
  o.height = 240;
  o.focal_start = 256;
  o.k1 = -0.05;
  o.supersampling = 1;
  const RenderedScene scene = RenderSyntheticScene(o);
  Reconstruction rec;
  std::filesystem::create_directories(out / "images");
  for (int i = 0; i < o.num_images; ++i) {
    rec.AddCamera(scene.cameras[i]);
    Image image;
    image.image_id = static_cast<image_t>(i + 1);
    image.camera_id = scene.cameras[i].camera_id;
    image.name = fmt::format("view{}.png", i);
    image.cam_from_world = scene.poses[i];
    image.registered = i < num_registered;
    rec.AddImage(image);
    WriteImage(out / "images" / image.name, scene.images[i]);
  }
  WriteColmapModel(rec, out / model);
  WriteMeshPly(out / "mesh.ply", testing::SyntheticSceneMesh());
}

TEST(TextureCommand, TexturesRendersAndScoresASyntheticScene) {
  TempDir tmp("texture_cli");
  const auto out = tmp.path();
  // `map`'s layout: --sparse takes the parent of the numbered models (model 0), render finds
  // OUT/sparse/0 from OUT, evaluate --render finds OUT/textured from OUT/sparse/0.
  WriteSyntheticInputs(out, 4, std::filesystem::path("sparse") / "0");
  std::string log;
  ASSERT_EQ(RunCommand(fmt::format("{} texture --mesh {} --sparse {} --images {} --output {}",
                                   ShellQuote(VarsfmBinary()), ShellQuote(out / "mesh.ply"),
                                   ShellQuote(out / "sparse"), ShellQuote(out / "images"),
                                   ShellQuote(out)),
                       &log),
            0)
      << log;
  for (const char* file :
       {"textured/model.obj", "textured/model.mtl", "textured/model_0.png", "model.glb"})
    EXPECT_TRUE(std::filesystem::is_regular_file(out / file)) << file;
  {
    int code = -1;
    std::string output, why;
    if (testing::ValidateGltf(out / "model.glb", &code, &output, &why)) {
      EXPECT_EQ(code, 0) << output;
    } else {
      std::printf("glTF validation skipped: %s\n", why.c_str());
    }
  }

  ASSERT_EQ(RunCommand(fmt::format("{} render --model {} --camera view2.png --output {}",
                                   ShellQuote(VarsfmBinary()), ShellQuote(out),
                                   ShellQuote(out / "view2_render.png")),
                       &log),
            0)
      << log;
  const cv::Mat rendered = ReadImagePixels(out / "view2_render.png");
  EXPECT_EQ(rendered.cols, 320);
  EXPECT_EQ(rendered.rows, 240);

  // No --gt: the rendering report alone.
  ASSERT_EQ(RunCommand(fmt::format("{} evaluate {} --render --images {} --json {}",
                                   ShellQuote(VarsfmBinary()), ShellQuote(out / "sparse" / "0"),
                                   ShellQuote(out / "images"), ShellQuote(out / "render.json")),
                       &log),
            0)
      << log;
  EXPECT_NE(log.find("PSNR"), std::string::npos) << log;
  const nlohmann::json report = nlohmann::json::parse(std::ifstream(out / "render.json"));
  ASSERT_EQ(report["images"].size(), 4u);
  EXPECT_GT(report["mean_psnr_db"].get<double>(), 25.0) << report.dump();
  EXPECT_GT(report["mean_coverage"].get<double>(), 0.85) << report.dump();
}

TEST(TextureCommand, BadInputIsAOneLineError) {
  TempDir tmp("texture_cli_bad");
  const auto out = tmp.path();
  WriteSyntheticInputs(out, 0);  // a model whose images are not registered: none written
  std::string log;
  const auto texture = [&](const std::filesystem::path& mesh) {
    return RunCommand(
        fmt::format("{} texture --mesh {} --sparse {} --images {} --output {}",
                    ShellQuote(VarsfmBinary()), ShellQuote(mesh), ShellQuote(out / "sparse"),
                    ShellQuote(out / "images"), ShellQuote(out / "o")),
        &log);
  };
  EXPECT_EQ(texture(out / "missing.ply"), 1);
  EXPECT_NE(log.find("varsfm: error:"), std::string::npos) << log;
  EXPECT_NE(log.find("missing.ply"), std::string::npos) << log;
  EXPECT_EQ(texture(out / "mesh.ply"), 1);
  EXPECT_NE(log.find("has 0 registered images; texture needs at least 1"), std::string::npos)
      << log;
  EXPECT_FALSE(std::filesystem::exists(out / "o" / "model.glb"));
  // Settings under which no photo sees any face: an error, not an untextured model.
  WriteSyntheticInputs(out, 3);
  EXPECT_EQ(RunCommand(fmt::format("{} texture --mesh {} --sparse {} --images {} --output {} "
                                   "--min-cos 1",
                                   ShellQuote(VarsfmBinary()), ShellQuote(out / "mesh.ply"),
                                   ShellQuote(out / "sparse"), ShellQuote(out / "images"),
                                   ShellQuote(out / "o")),
                       &log),
            1);
  EXPECT_NE(log.find("nothing to texture"), std::string::npos) << log;
  EXPECT_FALSE(std::filesystem::exists(out / "o" / "model.glb"));

  EXPECT_EQ(RunCommand(
                fmt::format("{} render --model {} --camera nope.png --output {}",
                            ShellQuote(VarsfmBinary()), ShellQuote(out), ShellQuote(out / "x.png")),
                &log),
            1);
  EXPECT_NE(log.find("no registered image named nope.png (it has 3: view0.png, view1.png, "
                     "view2.png)"),
            std::string::npos)
      << log;
  // Neither --gt nor --render: a usage error.
  EXPECT_EQ(RunCommand(fmt::format("{} evaluate {}", ShellQuote(VarsfmBinary()),
                                   ShellQuote(out / "sparse")),
                       &log),
            2);
  EXPECT_NE(log.find("--gt"), std::string::npos) << log;
  EXPECT_NE(RunCommand(fmt::format("{} run {} {} --until everything", ShellQuote(VarsfmBinary()),
                                   ShellQuote(out / "images"), ShellQuote(out / "run")),
                       &log),
            0);
  EXPECT_NE(log.find("--until"), std::string::npos) << log;
  EXPECT_FALSE(std::filesystem::exists(out / "run"));
}

}  // namespace
}  // namespace varsfm

namespace varsfm {
namespace {

// The novel-view protocol: with --holdout 2, views 0 and 2 (by name) texture nothing and are
// scored apart from the source views.
TEST(TextureCommand, HoldoutKeepsViewsOutAndScoresThemApart) {
  TempDir tmp("texture_holdout");
  const auto out = tmp.path();
  WriteSyntheticInputs(out, 4);
  std::string log;
  ASSERT_EQ(RunCommand(fmt::format(
                           "{} texture --mesh {} --sparse {} --images {} --output {} --holdout 2",
                           ShellQuote(VarsfmBinary()), ShellQuote(out / "mesh.ply"),
                           ShellQuote(out / "sparse"), ShellQuote(out / "images"), ShellQuote(out)),
                       &log),
            0)
      << log;
  EXPECT_NE(log.find("2 held-out view(s) left out"), std::string::npos) << log;
  ASSERT_EQ(RunCommand(fmt::format("{} evaluate {} --render --images {} --holdout 2 --json {}",
                                   ShellQuote(VarsfmBinary()), ShellQuote(out / "sparse"),
                                   ShellQuote(out / "images"), ShellQuote(out / "render.json")),
                       &log),
            0)
      << log;
  EXPECT_NE(log.find("2 held-out views"), std::string::npos) << log;
  const nlohmann::json report = nlohmann::json::parse(std::ifstream(out / "render.json"));
  EXPECT_EQ(report["held_out"]["images"], 2);
  EXPECT_EQ(report["source"]["images"], 2);
  for (const nlohmann::json& row : report["images"]) {
    const std::string name = row["name"];
    EXPECT_EQ(row["held_out"].get<bool>(), name == "view0.png" || name == "view2.png") << name;
  }
  EXPECT_GT(report["held_out"]["mean_coverage"].get<double>(), 0.5) << report.dump();
  EXPECT_GT(report["held_out"]["mean_ssim"].get<double>(), 0.5) << report.dump();
  EXPECT_EQ(RunCommand(fmt::format("{} texture --mesh {} --sparse {} --images {} --output {} "
                                   "--holdout 1",
                                   ShellQuote(VarsfmBinary()), ShellQuote(out / "mesh.ply"),
                                   ShellQuote(out / "sparse"), ShellQuote(out / "images"),
                                   ShellQuote(out / "o")),
                       &log) != 0,
            true);
  EXPECT_NE(log.find("--holdout: expected"), std::string::npos) << log;
}

}  // namespace
}  // namespace varsfm
