#pragma once
// Nearest-neighbour matching of SIFT/RootSIFT descriptors (uint8, 128 per row) with Lowe's ratio
// test and a mutual (cross) check, by exhaustive comparison. The distance is the angle between
// descriptors, acos(<a, b> / (|a| |b|)), as COLMAP's matcher uses; thresholds are COLMAP's
// defaults (SiftMatchingOptions: max_ratio 0.8, max_distance 0.7, cross_check on).
#include <memory>

#include "varsfm/feature/types.h"

namespace varsfm {

namespace internal {
struct PreparedDescriptors;
}

struct DescriptorMatchOptions {
  double max_ratio = 0.8;     // keep a match if its angle < max_ratio * second-best angle
  double max_distance = 0.7;  // and its angle (radians) <= max_distance
  // Keep i <-> j only if j is i's best match, i is j's best match, and both pass the tests.
  bool cross_check = true;
  // Use the AVX-512 VNNI kernel where the CPU has it (same results as the generic kernel).
  bool use_simd = true;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

// One image's descriptors converted once for matching and reused for each of its pairs.
class MatchableDescriptors {
 public:
  explicit MatchableDescriptors(const FeatureDescriptors& descriptors, bool use_simd = true);
  ~MatchableDescriptors();
  MatchableDescriptors(MatchableDescriptors&&) noexcept;
  MatchableDescriptors& operator=(MatchableDescriptors&&) noexcept;

  int size() const;
  const internal::PreparedDescriptors& prepared() const { return *prepared_; }

 private:
  std::unique_ptr<internal::PreparedDescriptors> prepared_;
};

// Matches of image 1's descriptors to image 2's, sorted by point2D_idx1. Both must have been
// prepared with the same use_simd; options.use_simd is ignored here.
FeatureMatches MatchDescriptors(const MatchableDescriptors& descriptors1,
                                const MatchableDescriptors& descriptors2,
                                const DescriptorMatchOptions& options);

// Convenience for a single pair.
FeatureMatches MatchDescriptors(const FeatureDescriptors& descriptors1,
                                const FeatureDescriptors& descriptors2,
                                const DescriptorMatchOptions& options = {});

}  // namespace varsfm
