// `densify` as the pipeline runs it: bad input (a missing, empty or one-image sparse model, or
// one too small to confirm any depth) stops with one varsfm::Error line, and nothing is written.
#include "varsfm/pipeline/densify.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "support/test_data.h"
#include "varsfm/io/colmap_model.h"
#include "varsfm/synthetic/rendered_scene.h"
#include "varsfm/synthetic/rendered_truth.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

using testing::TempDir;

// Runs densify on `model` and returns the error message ("" when it did not throw).
std::string DensifyError(const std::filesystem::path& model, const TempDir& tmp,
                         DensifyOptions options = {}) {
  options.sparse = model;
  options.image_dir = tmp.path();
  options.output = tmp.path() / "out";
  try {
    RunDensify(options);
  } catch (const Error& e) {
    EXPECT_FALSE(std::filesystem::exists(tmp.path() / "out" / "dense.ply"));
    return e.what();
  }
  return "";
}

TEST(DensifyCommand, MissingModelIsAnError) {
  const TempDir tmp("densify_missing");
  const std::string message = DensifyError(tmp.path() / "nope", tmp);
  EXPECT_NE(message.find("nope"), std::string::npos) << message;
}

TEST(DensifyCommand, EmptyModelIsAnError) {
  const TempDir tmp("densify_empty");
  WriteColmapModel(Reconstruction{}, tmp.path() / "sparse");
  const std::string message = DensifyError(tmp.path() / "sparse", tmp);
  EXPECT_NE(message.find("sparse"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(DensifyCommand, OneImageModelIsAnError) {
  const TempDir tmp("densify_one");
  Reconstruction one;
  Camera camera = Camera::FromFocal(320, 240, 300);
  camera.camera_id = 1;
  one.AddCamera(camera);
  Image image;
  image.image_id = 1;
  image.camera_id = 1;
  image.name = "a.png";
  image.registered = true;
  one.AddImage(image);
  WriteColmapModel(one, tmp.path() / "sparse");
  const std::string message = DensifyError(tmp.path() / "sparse", tmp);
  EXPECT_NE(message.find("1 registered image"), std::string::npos) << message;
  EXPECT_NE(message.find("sparse"), std::string::npos) << message;
}

// Two true views of the rendered scene. By default a confident depth stands on one confirming
// view, so the two views give a cloud. Where every depth needs two confirming views
// (--dense-two-view-cost 0), no point can come out, and the error says so instead of a later
// stage meeting an empty dense.ply.
TEST(DensifyCommand, TwoImageModelGivesPointsOrExplainsTheEmptyCloud) {
  const TempDir tmp("densify_two");
  RenderedSceneOptions render;
  render.num_images = 2;
  render.width = 160;
  render.height = 120;
  render.focal_start = 0.8 * render.width;
  const RenderedScene scene = RenderSyntheticScene(render);
  WriteRenderedScene(scene, tmp.path(), tmp.path() / "gt");
  Reconstruction rec = SparseModelFromRenderedScene(scene, 8);
  int index = 0;  // the model's images in the order, and under the names, they were written
  for (const auto& [id, image] : rec.images())
    rec.image(id).name = fmt::format("image_{:04d}.png", index++);
  WriteColmapModel(rec, tmp.path() / "sparse");
  EXPECT_EQ(DensifyError(tmp.path() / "sparse", tmp), "");
  EXPECT_GT(std::filesystem::file_size(tmp.path() / "out" / "dense.ply"), 1000u);

  std::filesystem::remove_all(tmp.path() / "out");
  DensifyOptions strict;
  strict.dense.mvs.fusion.two_view_max_cost = 0;
  const std::string message = DensifyError(tmp.path() / "sparse", tmp, strict);
  EXPECT_NE(message.find("2 registered images"), std::string::npos) << message;
  EXPECT_NE(message.find("3 views agree"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;

  // Held-out views are counted apart: the model has two, the stage is left one.
  DensifyOptions held_out;
  held_out.holdout = 2;
  const std::string few = DensifyError(tmp.path() / "sparse", tmp, held_out);
  EXPECT_NE(few.find("has 2 registered images, 1 left once --holdout 2 keeps 1 out"),
            std::string::npos)
      << few;
}

}  // namespace
}  // namespace varsfm
