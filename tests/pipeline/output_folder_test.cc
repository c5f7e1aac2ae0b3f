// The guards of a folder `run` and `map` rewrite, and the removal of a later stage's stale
// outputs (pipeline/output_folder.h).
#include <gtest/gtest.h>

#include <fstream>

#include "support/test_data.h"
#include "varsfm/pipeline/output_folder.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

// A folder holding every stage's outputs and a file of the user's.
void WriteEveryOutput(const fs::path& dir) {
  fs::create_directories(dir / "textured");
  for (const char* name : {"dense.ply", "dense.ply.vis", "dense_summary.json", "mesh.ply",
                           "model.glb", "textured/model.obj", "report.html", "notes.txt"})
    std::ofstream(dir / name) << "x";
}

TEST(RemoveOutputsAfter, RemovesWhatTheLaterStagesWroteInAVarsfmFolder) {
  TempDir tmp("outputs_after");
  const fs::path out = tmp.path() / "out";
  WriteEveryOutput(out);
  std::ofstream(out / "summary.json") << "{}";
  RemoveOutputsAfter(out, ChainStage::kDensify);
  for (const char* kept : {"dense.ply", "dense.ply.vis", "dense_summary.json", "notes.txt"})
    EXPECT_TRUE(fs::exists(out / kept)) << kept;
  for (const char* gone : {"mesh.ply", "model.glb", "textured", "report.html"})
    EXPECT_FALSE(fs::exists(out / gone)) << gone;

  WriteEveryOutput(out);
  RemoveOutputsAfter(out, ChainStage::kTexture);
  EXPECT_TRUE(fs::exists(out / "model.glb"));
  EXPECT_FALSE(fs::exists(out / "report.html"));
  RemoveOutputsAfter(out, ChainStage::kMap);
  for (const char* gone : {"dense.ply", "mesh.ply", "textured", "model.glb"})
    EXPECT_FALSE(fs::exists(out / gone)) << gone;
  EXPECT_TRUE(fs::exists(out / "notes.txt"));
}

TEST(RemoveOutputsAfter, LeavesAFolderVarsfmDidNotWriteAlone) {
  TempDir tmp("outputs_after_foreign");
  const fs::path out = tmp.path() / "out";
  WriteEveryOutput(out);
  RemoveOutputsAfter(out, ChainStage::kMap);
  EXPECT_TRUE(fs::exists(out / "mesh.ply"));
  EXPECT_TRUE(fs::exists(out / "textured" / "model.obj"));
  EXPECT_THROW(CheckOutputFolderIsOurs(out), Error);
  EXPECT_NO_THROW(CheckOutputFolderIsOurs(tmp.path() / "new"));
  fs::create_directories(tmp.path() / "empty");
  EXPECT_NO_THROW(CheckOutputFolderIsOurs(tmp.path() / "empty"));
}

// A disk that fills between the cloud and its visibility left a new dense.ply beside the last
// run's dense.ply.vis (or none): the pair is removed with the error.
TEST(WriteOutputsTogether, AFailedWriteRemovesTheWholeSet) {
  TempDir tmp("outputs_together");
  const fs::path out = tmp.path() / "out";
  WriteEveryOutput(out);
  EXPECT_THROW(WriteOutputsTogether(out, ChainStage::kDensify,
                                    [&] {
                                      std::ofstream(out / "dense.ply") << "new";
                                      Fail("{}: write failed (disk full?)", "dense.ply.vis");
                                    }),
               Error);
  EXPECT_FALSE(fs::exists(out / "dense.ply"));
  EXPECT_FALSE(fs::exists(out / "dense.ply.vis"));
  EXPECT_TRUE(fs::exists(out / "notes.txt"));

  WriteOutputsTogether(out, ChainStage::kTexture,
                       [&] { std::ofstream(out / "model.glb") << "new"; });
  EXPECT_TRUE(fs::exists(out / "textured" / "model.obj"));
  EXPECT_TRUE(fs::exists(out / "model.glb"));
}

TEST(CheckOutputOutsideImages, ThePhotoFolderAndFoldersInsideItAreRefused) {
  TempDir tmp("outside_images");
  const fs::path photos = tmp.path() / "photos";
  fs::create_directories(photos / "sub");
  EXPECT_THROW(CheckOutputOutsideImages(photos, photos), Error);
  EXPECT_THROW(CheckOutputOutsideImages(photos / "out", photos), Error);
  EXPECT_THROW(CheckOutputOutsideImages(photos / "sub" / ".." / "x", photos / "."), Error);
  EXPECT_NO_THROW(CheckOutputOutsideImages(tmp.path() / "photos2", photos));
  EXPECT_NO_THROW(CheckOutputOutsideImages(tmp.path() / "out", photos / "sub"));
  // A folder that cannot be made is left to the stage that makes it, with its own error.
  std::ofstream(photos / "file") << "x";
  EXPECT_NO_THROW(CheckOutputOutsideImages(photos / "file" / "out", photos));
}

}  // namespace
}  // namespace varsfm
