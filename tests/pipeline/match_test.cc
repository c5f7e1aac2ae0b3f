// End to end through the command-line tool: `varsfm extract` then `varsfm match` on a real
// photo sequence, checked in the workspace database.
#include <algorithm>
#include <random>
#include <stdexcept>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "support/test_data.h"
#include "varsfm/io/database.h"
#include "varsfm/pipeline/match.h"

namespace varsfm {
namespace {

using testing::RunCommand;
using testing::ShellQuote;
using testing::TempDir;
using testing::VarsfmBinary;

TEST(MatchCommand, KermitAdjacentPairsAreVerified) {
  VARSFM_REQUIRE_SHARED_DATA(images, "bundler/kermit");
  TempDir dir("match_kermit");
  const auto workspace = dir.path() / "ws.db";
  std::string out;
  ASSERT_EQ(
      RunCommand(fmt::format("{} extract --workspace {} --images {}", ShellQuote(VarsfmBinary()),
                             ShellQuote(workspace), ShellQuote(images)),
                 &out),
      0)
      << out;
  const std::string match = fmt::format("{} match --workspace {} --strategy exhaustive",
                                        ShellQuote(VarsfmBinary()), ShellQuote(workspace));
  ASSERT_EQ(RunCommand(match, &out), 0) << out;

  Database db(workspace);
  std::vector<DbImage> sorted = db.ReadAllImages();
  ASSERT_EQ(sorted.size(), 11u);
  std::sort(sorted.begin(), sorted.end(),
            [](const DbImage& a, const DbImage& b) { return a.name < b.name; });
  // Every pair was matched and has a geometry row (empty when unverified, as COLMAP).
  EXPECT_EQ(db.NumMatchedPairs(), 55u);
  EXPECT_EQ(db.ReadAllTwoViewGeometries().size(), 55u);
  // Consecutive photos of the sequence mostly overlap and see a 3D scene. Kermit has wide
  // baselines: measured with ~1k features per image, 8 of its 10 consecutive pairs verify (5
  // with >= 100 inliers); COLMAP 3.8 verifies 9 (its 006-007 fails too). Margins below allow
  // for extractor changes.
  int verified = 0, strong = 0;
  for (size_t k = 0; k + 1 < sorted.size(); ++k) {
    const image_t id1 = sorted[k].image_id, id2 = sorted[k + 1].image_id;
    const TwoViewGeometry g = db.ReadTwoViewGeometry(id1, id2);
    SCOPED_TRACE(sorted[k].name + " - " + sorted[k + 1].name);
    // The stored inliers are a subset of the stored raw matches.
    EXPECT_GE(db.ReadMatches(id1, id2).size(), g.inlier_matches.size());
    if (g.inlier_matches.empty()) {
      EXPECT_EQ(g.config, TwoViewGeometry::kUndefined);  // COLMAP's empty geometry
      continue;
    }
    EXPECT_GE(g.inlier_matches.size(), 15u);
    EXPECT_EQ(g.config, TwoViewGeometry::kUncalibrated);
    ++verified;
    strong += g.inlier_matches.size() >= 100;
  }
  EXPECT_GE(verified, 7);
  EXPECT_GE(strong, 4);

  // A second run finds every pair verified and changes nothing.
  ASSERT_EQ(RunCommand(match, &out), 0) << out;
  EXPECT_NE(out.find("55 already verified"), std::string::npos) << out;
}

// A workspace of `num_images` images with random features (their pairs do not verify, which is
// all the tests of the bookkeeping below need).
void WriteRandomFeatures(const std::filesystem::path& workspace, int num_images) {
  Database db(workspace);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> coordinate(0, 400);
  std::uniform_int_distribution<int> value(0, 60);
  for (int i = 0; i < num_images; ++i) {
    FeatureKeypoints keypoints;
    FeatureDescriptors descriptors(100, 128);
    for (int k = 0; k < 100; ++k) {
      keypoints.emplace_back(coordinate(rng), coordinate(rng));
      for (int c = 0; c < 128; ++c) descriptors(k, c) = static_cast<uint8_t>(value(rng));
    }
    const camera_t camera = db.WriteCamera({0, 2, 400, 400, {480, 200, 200, 0}, false});
    const image_t image = db.WriteImage({0, fmt::format("{}.png", i), camera});
    db.WriteKeypoints(image, keypoints);
    db.WriteDescriptors(image, descriptors);
  }
}

// Verified pairs are committed by time as well as by count: a run killed (here: an error from
// the clock) while writing the 21st of 28 pairs keeps the 18 committed by then, and the next
// run resumes from there.
TEST(MatchPipeline, AKilledRunKeepsWhatItCommittedByTime) {
  TempDir dir("match_commit_by_time");
  const auto workspace = dir.path() / "ws.db";
  WriteRandomFeatures(workspace, 8);  // 28 pairs
  MatchOptions options;
  options.workspace = workspace;
  options.num_threads = 2;
  options.commit_interval = 3.0;
  // Each reading of the clock advances it by one second: one when matching starts, one per pair
  // written; the 22nd fails like a kill.
  int readings = 0;
  options.clock = [&readings] {
    if (++readings == 22) throw std::runtime_error("killed");
    return static_cast<double>(readings);
  };
  EXPECT_THROW(RunMatching(options), std::runtime_error);
  size_t kept = 0;
  {
    Database db(workspace);
    kept = db.ReadAllTwoViewGeometries().size();
    EXPECT_EQ(db.NumMatchedPairs(), kept);  // each pair whole
  }
  EXPECT_EQ(kept, 18u);  // commits every 3 s of the clock: after pairs 3, 6, ..., 18

  options.clock = nullptr;
  const MatchSummary resumed = RunMatching(options);
  EXPECT_EQ(resumed.num_skipped, kept);
  EXPECT_EQ(Database(workspace).ReadAllTwoViewGeometries().size(), 28u);
}

// Photos that share nothing: no silent success, a warning says that no pair verified.
TEST(MatchCommand, NoVerifiedPairIsNamedInAWarning) {
  TempDir dir("match_none_verified");
  const auto workspace = dir.path() / "ws.db";
  WriteRandomFeatures(workspace, 4);
  std::string out;
  EXPECT_EQ(RunCommand(fmt::format("{} match --workspace {}", ShellQuote(VarsfmBinary()),
                                   ShellQuote(workspace)),
                       &out),
            0)
      << out;
  EXPECT_NE(out.find("0 of 6 new pairs verified"), std::string::npos) << out;
  EXPECT_NE(out.find("no pair of images shares a verified geometry"), std::string::npos) << out;
}

// Pairs are recorded with the settings they were matched with: a re-run with other settings
// matches every pair again (those that failed too), one with only another thread count skips
// them all.
TEST(MatchPipeline, OtherSettingsMatchAgainAndThreadsChangeNothing) {
  TempDir dir("match_settings");
  const auto workspace = dir.path() / "ws.db";
  WriteRandomFeatures(workspace, 5);  // 10 pairs
  MatchOptions options;
  options.workspace = workspace;
  options.num_threads = 2;
  options.matching.max_ratio = 0.95;
  EXPECT_EQ(RunMatching(options).num_skipped, 0u);
  const auto count_matches = [&] {
    Database db(workspace);
    size_t count = 0;
    for (image_t id1 = 1; id1 <= 5; ++id1) {
      for (image_t id2 = id1 + 1; id2 <= 5; ++id2) count += db.ReadMatches(id1, id2).size();
    }
    return count;
  };
  const size_t loose = count_matches();
  ASSERT_GT(loose, 0u);

  options.num_threads = 1;
  EXPECT_EQ(RunMatching(options).num_skipped, 10u);

  options.matching.max_ratio = 0.6;  // fewer matches
  EXPECT_EQ(RunMatching(options).num_skipped, 0u);
  EXPECT_LT(count_matches(), loose);
  EXPECT_EQ(RunMatching(options).num_skipped, 10u);

  // A pair that failed verification is tried again under other verification settings.
  options.verification.min_num_inliers = 8;
  EXPECT_EQ(RunMatching(options).num_skipped, 0u);

  // Switching DEGENSAC off, or another local optimisation, matches again.
  options.verification.degeneracy_recovery = false;
  EXPECT_EQ(RunMatching(options).num_skipped, 0u);
  options.verification.method = RansacMethod::kLoRansac;
  EXPECT_EQ(RunMatching(options).num_skipped, 0u);
  options.verification.degeneracy_recovery = true;
  EXPECT_EQ(RunMatching(options).num_skipped, 0u);
  EXPECT_EQ(RunMatching(options).num_skipped, 10u);
}

TEST(MatchCommand, BadWorkspacesFailWithOneLine) {
  TempDir dir("match_bad");
  const auto missing = dir.path() / "missing.db";
  std::string out;
  EXPECT_EQ(RunCommand(fmt::format("{} match --workspace {}", ShellQuote(VarsfmBinary()),
                                   ShellQuote(missing)),
                       &out),
            1);
  EXPECT_NE(out.find("does not exist"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(missing));  // not created

  VARSFM_REQUIRE_SHARED_DATA(images, "bundler/kermit");
  const auto one = dir.path() / "one";
  std::filesystem::create_directories(one);
  std::filesystem::copy_file(images / "kermit000.jpg", one / "kermit000.jpg");
  const auto workspace = dir.path() / "one.db";
  ASSERT_EQ(
      RunCommand(fmt::format("{} extract --workspace {} --images {}", ShellQuote(VarsfmBinary()),
                             ShellQuote(workspace), ShellQuote(one)),
                 &out),
      0)
      << out;
  EXPECT_EQ(RunCommand(fmt::format("{} match --workspace {}", ShellQuote(VarsfmBinary()),
                                   ShellQuote(workspace)),
                       &out),
            1);
  EXPECT_NE(out.find("needs at least 2"), std::string::npos) << out;
  EXPECT_EQ(Database(workspace).NumMatchedPairs(), 0u);
}

}  // namespace
}  // namespace varsfm
