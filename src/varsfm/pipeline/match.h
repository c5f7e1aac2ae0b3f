#pragma once
// `varsfm match`: matches the features of a workspace's images pair by pair and verifies each
// pair geometrically, storing raw matches and two-view geometries in the workspace database
// (COLMAP's schema, so COLMAP can continue from it).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

#include "varsfm/matching/descriptor_matcher.h"
#include "varsfm/matching/geometric_verification.h"
#include "varsfm/matching/image_retrieval.h"
#include "varsfm/matching/vocabulary_tree.h"
#include "varsfm/util/enum_names.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/random.h"

namespace varsfm {

// Which image pairs are matched.
enum class MatchStrategy {
  kExhaustive,  // every pair
  kSequential,  // each image with the next `overlap` in name order (video, walked sequences),
                // plus retrieval every `loop_interval` images (loop closure)
  kRetrieval,   // each image with its top-k retrieved images (vocabulary tree)
  kAuto,        // exhaustive up to kAutoRetrievalImages images, retrieval above
};

// kAuto matches exhaustively up to this many images and by retrieval above: where exhaustive
// matching's n(n-1)/2 pairs cost as much as retrieval's pairs (about 0.6 n k) plus training the
// tree, measured on a rendered 240-image walk (bench/results/2026-12-02-retrieval.md).
inline constexpr size_t kAutoRetrievalImages = 100;

// The names the command line takes and summaries give.
inline constexpr EnumName<MatchStrategy> kMatchStrategyNames[] = {
    {MatchStrategy::kExhaustive, "exhaustive"},
    {MatchStrategy::kSequential, "sequential"},
    {MatchStrategy::kRetrieval, "retrieval"},
    {MatchStrategy::kAuto, "auto"}};

struct MatchOptions {
  std::filesystem::path workspace;  // must exist, with features from `varsfm extract`
  MatchStrategy strategy = MatchStrategy::kExhaustive;
  int overlap = 10;  // sequential: each image with its next `overlap`
  // Sequential: every loop_interval-th image also with its retrieved neighbours (0: none).
  int loop_interval = 0;
  RetrievalOptions retrieval;        // retrieval and loop closure
  VocabularyTreeOptions vocabulary;  // its seed is replaced by `seed`
  // Descriptors sampled evenly over the images to train the tree on.
  int vocabulary_sample = 200000;
  // A vocabulary tree file: read if it exists, else trained and written there (empty: trained,
  // not kept).
  std::filesystem::path vocabulary_file;
  DescriptorMatchOptions matching;
  VerificationOptions verification;  // its seed is replaced by one derived per pair
  uint64_t seed = kDefaultSeed;
  int num_threads = 0;  // 0: all cores
  // Verified pairs are committed at least this often (seconds), so a kill loses at most this
  // much work.
  double commit_interval = 1.0;
  // Seconds on a monotonic clock, for the commits; empty: std::chrono::steady_clock. Tests
  // give their own to commit (and fail) at chosen points without waiting.
  std::function<double()> clock;

  // Throws OptionError (util/option_check.h) for a bad value; the workspace is checked by
  // RunMatching.
  void Check() const;
};

struct MatchSummary {
  MatchStrategy strategy = MatchStrategy::kExhaustive;  // the one used (kAuto resolved)
  size_t num_images = 0;                                // images with features
  size_t num_pairs = 0;                                 // pairs the strategy selects
  size_t num_skipped = 0;                               // already verified in an earlier run
  size_t num_verified = 0;        // newly matched pairs with a stored (non-empty) geometry
  size_t num_inlier_matches = 0;  // over the newly verified pairs
};

// Throws OptionError for a bad option and varsfm::Error (workspace untouched) if the workspace
// is missing or has fewer than two images with features. Pairs already holding a two-view
// geometry are skipped, so an interrupted run resumes; a pair's matches and geometry are
// committed together, pairs as they are verified, at least every options.commit_interval
// seconds.
MatchSummary RunMatching(const MatchOptions& options, OptionsCheck check = OptionsCheck::kByStage);

}  // namespace varsfm
