// Retrieval on a rendered walk with exact truth: a street walked out and back (the return 1 m
// nearer the facade, looking the other way ahead), so frame k going out and frame n - 1 - k
// coming back see the same stretch. Each frame's retrieved images are frames that see the same
// stretch, the same at any thread count; sequential matching with loop closure links the walk's
// end to its start; a saved vocabulary tree is reused and a corrupt one refused.
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "support/test_data.h"
#include "varsfm/io/database.h"
#include "varsfm/matching/pair_selection.h"
#include "varsfm/pipeline/extract.h"
#include "varsfm/pipeline/match.h"
#include "varsfm/pipeline/retrieval_neighbors.h"
#include "varsfm/synthetic/rendered_scene.h"
#include "varsfm/util/error.h"
#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

constexpr int kFrames = 20;
constexpr double kStep = 0.5;  // metres along the street per frame

// Where along the street frame i stands (as RenderSyntheticScene's kStreetAndBack).
double StreetPosition(int i) {
  const int turn = (kFrames - 1) / 2;
  return kStep * (i > turn ? 2 * turn + 1 - i : i);
}

class RetrievalOnRenderedWalk : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // ctest runs each test in its own process, possibly at once: a folder per process.
    tmp_ = new testing::TempDir("retrieval_walk_" + std::to_string(::getpid()));
    RenderedSceneOptions scene;
    scene.path = CameraPath::kStreetAndBack;
    scene.street_step = kStep;
    scene.num_images = kFrames;
    scene.width = 320;
    scene.height = 240;
    scene.focal_start = 256;
    scene.supersampling = 1;
    WriteRenderedScene(RenderSyntheticScene(scene), tmp_->path() / "images", tmp_->path() / "gt");
    ExtractOptions extract;
    extract.workspace = tmp_->path() / "workspace.db";
    extract.image_dir = tmp_->path() / "images";
    RunExtraction(extract);
  }
  static void TearDownTestSuite() { delete tmp_; }

  static std::vector<image_t> Images(const Database& db) {
    std::vector<DbImage> images = db.ReadAllImages();
    std::sort(images.begin(), images.end(),
              [](const DbImage& a, const DbImage& b) { return a.name < b.name; });
    std::vector<image_t> ids;
    for (const DbImage& image : images) ids.push_back(image.image_id);
    return ids;
  }

  static MatchOptions Options() {
    MatchOptions options;
    options.workspace = tmp_->path() / "workspace.db";
    options.retrieval.num_neighbors = 3;
    return options;
  }

  static testing::TempDir* tmp_;
};

testing::TempDir* RetrievalOnRenderedWalk::tmp_ = nullptr;

TEST_F(RetrievalOnRenderedWalk, RetrievesFramesOfTheSameStretch) {
  const Database db(tmp_->path() / "workspace.db");
  const std::vector<image_t> images = Images(db);
  ASSERT_EQ(images.size(), static_cast<size_t>(kFrames));
  const MatchOptions options = Options();
  std::vector<std::vector<uint32_t>> one, two;
  {
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 1);
    one = RetrieveNeighbors(db, images, std::vector<bool>(kFrames, true), options);
  }
  {
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
    two = RetrieveNeighbors(db, images, std::vector<bool>(kFrames, true), options);
  }
  EXPECT_EQ(one, two);
  // A frame sees about 5 m of the facade at zoom x1: frames within 1.5 m of each other share
  // most of what they see.
  for (int i = 0; i < kFrames; ++i) {
    ASSERT_EQ(one[i].size(), 3u) << i;
    for (const uint32_t j : one[i])
      EXPECT_LE(std::abs(StreetPosition(i) - StreetPosition(static_cast<int>(j))), 1.5 + 1e-9)
          << "frame " << i << " retrieved frame " << j;
  }
}

TEST_F(RetrievalOnRenderedWalk, LoopClosureLinksTheEndToTheStart) {
  const Database db(tmp_->path() / "workspace.db");
  const std::vector<image_t> images = Images(db);
  MatchOptions options = Options();
  options.loop_interval = 5;
  std::vector<bool> is_query(kFrames, false);
  for (int i = 0; i < kFrames; i += options.loop_interval) is_query[i] = true;
  const ImagePairs pairs = SequentialLoopPairs(images, 2, options.loop_interval,
                                               RetrieveNeighbors(db, images, is_query, options, 2));
  // Every pair beyond the sequential overlap sees one stretch of the street; one of them links
  // a frame of the way back to one of the way out near the start (the first 2.5 m).
  bool closed = false;
  const int turn = (kFrames - 1) / 2;
  for (const auto& [a, b] : pairs) {
    const int i = static_cast<int>(a - images[0]), j = static_cast<int>(b - images[0]);
    if (j - i <= 2) continue;
    EXPECT_LE(std::abs(StreetPosition(i) - StreetPosition(j)), 2.5 + 1e-9) << i << " " << j;
    closed |= i <= turn && j > turn && StreetPosition(i) <= 2.5 && StreetPosition(j) <= 2.5;
  }
  EXPECT_TRUE(closed);
  EXPECT_LT(pairs.size(), ExhaustivePairs(images).size() / 3);
}

TEST_F(RetrievalOnRenderedWalk, VocabularyFileIsSavedReusedAndCheckedWhenCorrupt) {
  const auto workspace = tmp_->path() / "match.db";
  std::filesystem::copy_file(tmp_->path() / "workspace.db", workspace,
                             std::filesystem::copy_options::overwrite_existing);
  MatchOptions options = Options();
  options.workspace = workspace;
  options.strategy = MatchStrategy::kRetrieval;
  options.vocabulary_file = tmp_->path() / "tree.voc";
  const MatchSummary first = RunMatching(options);
  EXPECT_EQ(first.strategy, MatchStrategy::kRetrieval);
  EXPECT_GE(first.num_pairs, static_cast<size_t>(kFrames * 3 / 2));
  EXPECT_LE(first.num_pairs, static_cast<size_t>(kFrames * 3));
  ASSERT_TRUE(std::filesystem::exists(options.vocabulary_file));
  // Reused: the same pairs, all already verified.
  const MatchSummary second = RunMatching(options);
  EXPECT_EQ(second.num_pairs, first.num_pairs);
  EXPECT_EQ(second.num_skipped, first.num_pairs);

  std::fstream file(options.vocabulary_file, std::ios::in | std::ios::out | std::ios::binary);
  file.seekp(100);
  file.put('\x5a');
  file.close();
  try {
    RunMatching(options);
    ADD_FAILURE() << "a corrupt vocabulary tree was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("corrupt"), std::string::npos) << e.what();
  }
  options.vocabulary.depth = 0;
  EXPECT_THROW(RunMatching(options), OptionError);
}

}  // namespace
}  // namespace varsfm
