#pragma once
// `varsfm match`: matches the features of a workspace's images pair by pair and verifies each
// pair geometrically, storing raw matches and two-view geometries in the workspace database
// (COLMAP's schema, so COLMAP can continue from it).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "varsfm/matching/descriptor_matcher.h"
#include "varsfm/matching/geometric_verification.h"
#include "varsfm/util/random.h"

namespace varsfm {

struct MatchOptions {
  std::filesystem::path workspace;      // must exist, with features from `varsfm extract`
  std::string strategy = "exhaustive";  // "exhaustive" or "sequential"
  int overlap = 10;                     // sequential: each image with its next `overlap`
  DescriptorMatchOptions matching;
  VerificationOptions verification;  // its seed is replaced by one derived per pair
  uint64_t seed = kDefaultSeed;
  int num_threads = 0;  // 0: all cores
};

struct MatchSummary {
  size_t num_images = 0;          // images with features
  size_t num_pairs = 0;           // pairs the strategy selects
  size_t num_skipped = 0;         // already verified in an earlier run
  size_t num_verified = 0;        // newly matched pairs with a stored (non-empty) geometry
  size_t num_inlier_matches = 0;  // over the newly verified pairs
};

// Throws varsfm::Error (workspace untouched) if the workspace is missing or has fewer than two
// images with features. Pairs already holding a two-view geometry are skipped, so an
// interrupted run resumes; each pair's matches and geometry are written in one transaction.
MatchSummary RunMatching(const MatchOptions& options);

}  // namespace varsfm
