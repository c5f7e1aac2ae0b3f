// The sparse model the stages after `map` read (pipeline/stage_model.h): a photo the stage would
// read and cannot find is a one-line error before any work, one a held-out view would have been
// is not needed.
#include "varsfm/pipeline/stage_model.h"

#include <fstream>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "support/test_data.h"
#include "varsfm/io/colmap_model.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

using testing::TempDir;

// A model of four registered images view0.png .. view3.png in TMP/sparse, and TMP/images with
// every photo but `missing` (only whether a file is there is read).
void WriteModelAndPhotos(const TempDir& tmp, const std::string& missing) {
  Reconstruction rec;
  Camera camera = Camera::FromFocal(320, 240, 300);
  camera.camera_id = 1;
  rec.AddCamera(camera);
  std::filesystem::create_directories(tmp.path() / "images");
  for (int i = 0; i < 4; ++i) {
    Image image;
    image.image_id = static_cast<image_t>(i + 1);
    image.camera_id = 1;
    image.name = fmt::format("view{}.png", i);
    image.registered = true;
    rec.AddImage(image);
    if (image.name != missing) std::ofstream(tmp.path() / "images" / image.name) << "photo";
  }
  WriteColmapModel(rec, tmp.path() / "sparse");
}

// ReadStageModel's error message ("" when it did not throw).
std::string StageModelError(const TempDir& tmp, int holdout) {
  try {
    ReadStageModel("densify", tmp.path() / "sparse", tmp.path() / "images", holdout, 2);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(StageModel, MissingPhotoIsAnError) {
  const TempDir tmp("stage_model_missing");
  WriteModelAndPhotos(tmp, "view1.png");
  const std::string message = StageModelError(tmp, 0);
  EXPECT_NE(message.find(fmt::format("densify: 1 of the model's 4 registered photos are not in {} "
                                     "(the first: view1.png)",
                                     (tmp.path() / "images").string())),
            std::string::npos)
      << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(StageModel, HeldOutViewsNeedNoPhoto) {
  const TempDir tmp("stage_model_held_out");
  // --holdout 2 keeps view0 and view2 out (every second registered image by name, from the
  // first): their photos are not read.
  WriteModelAndPhotos(tmp, "view0.png");
  EXPECT_EQ(StageModelError(tmp, 2), "");
  EXPECT_NE(StageModelError(tmp, 0).find("view0.png"), std::string::npos);
}

TEST(StageModel, EveryPhotoThereReadsTheModel) {
  const TempDir tmp("stage_model_complete");
  WriteModelAndPhotos(tmp, "");
  const Reconstruction rec =
      ReadStageModel("texture", tmp.path() / "sparse", tmp.path() / "images", 0, 1);
  EXPECT_EQ(rec.NumRegisteredImages(), 4u);
}

}  // namespace
}  // namespace varsfm
