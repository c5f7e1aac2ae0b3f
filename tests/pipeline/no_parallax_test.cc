// A capture without parallax (the camera turning about its centre) cannot be reconstructed:
// `run` says why in one line, without advising the `varsfm match` it has just run, and leaves no
// output folder behind it (but never removes one that was there).
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "support/test_data.h"
#include "varsfm/synthetic/rendered_scene.h"

namespace varsfm {
namespace {

using testing::RunCommand;
using testing::ShellQuote;
using testing::TempDir;
using testing::VarsfmBinary;

// Six views of the synthetic room from one centre (an orbit of zero arc: only the look-at
// jitter and the zoom change between them), so every pair is related by a homography.
void WriteRotationOnlyImages(const std::filesystem::path& image_dir) {
  RenderedSceneOptions options;
  options.num_images = 6;
  options.width = 400;
  options.height = 300;
  options.focal_start = 320;
  options.zoom = 1.2;
  options.arc_degrees = 0;
  options.supersampling = 1;
  WriteRenderedScene(RenderSyntheticScene(options), image_dir, image_dir.parent_path() / "gt");
}

TEST(NoParallax, RunSaysWhyAndLeavesNoFolder) {
  TempDir tmp("no_parallax");
  const auto images = tmp.path() / "images";
  WriteRotationOnlyImages(images);

  const auto out = tmp.path() / "out";
  std::string errors;
  const int code =
      RunCommand(fmt::format("( {} run {} {} --until sparse 2>&1 >/dev/null )",
                             ShellQuote(VarsfmBinary()), ShellQuote(images), ShellQuote(out)),
                 &errors);
  EXPECT_EQ(code, 1) << errors;
  // The last line is the error; the lines before are the stages' log.
  const std::string last = errors.substr(errors.rfind("varsfm: error: "));
  EXPECT_NE(last.find("all 15 verified image pairs are related by a homography"), std::string::npos)
      << last;
  EXPECT_NE(last.find("no parallax"), std::string::npos) << last;
  EXPECT_EQ(errors.find("varsfm match"), std::string::npos) << errors;
  EXPECT_EQ(errors.find(".tmp"), std::string::npos) << errors;
  EXPECT_FALSE(std::filesystem::exists(out)) << "a failed run removes the folder it created";

  // A folder that was there (with content) stays, content and all.
  std::filesystem::create_directories(out);
  std::ofstream(out / "notes.txt") << "mine\n";
  EXPECT_EQ(RunCommand(fmt::format("{} run {} {} --until sparse", ShellQuote(VarsfmBinary()),
                                   ShellQuote(images), ShellQuote(out))),
            1);
  EXPECT_TRUE(std::filesystem::is_regular_file(out / "notes.txt"));
}

}  // namespace
}  // namespace varsfm
