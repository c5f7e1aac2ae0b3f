#include "varsfm/matching/descriptor_matcher.h"

#include <algorithm>
#include <cmath>

#include "varsfm/matching/nearest_neighbors.h"
#include "varsfm/util/error.h"
#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

internal::NnKernel ChooseKernel(bool use_simd) {
  static const bool has_vnni = internal::CpuHasAvx512Vnni();
  return use_simd && has_vnni ? internal::NnKernel::kAvx512Vnni : internal::NnKernel::kGeneric;
}

// COLMAP's one-way test: the best angle is small enough and clearly smaller than the second.
bool PassesRatioTest(float best_score, float second_score, const DescriptorMatchOptions& options) {
  const double best = std::acos(std::clamp(best_score, -1.0f, 1.0f));
  if (best > options.max_distance) return false;
  const double second = std::acos(std::clamp(second_score, -1.0f, 1.0f));
  return best < options.max_ratio * second;
}

}  // namespace

MatchableDescriptors::MatchableDescriptors(const FeatureDescriptors& descriptors, bool use_simd)
    : prepared_(std::make_unique<internal::PreparedDescriptors>(
          internal::PrepareDescriptors(descriptors, ChooseKernel(use_simd)))) {}
MatchableDescriptors::~MatchableDescriptors() = default;
MatchableDescriptors::MatchableDescriptors(MatchableDescriptors&&) noexcept = default;
MatchableDescriptors& MatchableDescriptors::operator=(MatchableDescriptors&&) noexcept = default;

int MatchableDescriptors::size() const { return prepared_->num; }

FeatureMatches MatchDescriptors(const MatchableDescriptors& descriptors1,
                                const MatchableDescriptors& descriptors2,
                                const DescriptorMatchOptions& options) {
  const auto& a = descriptors1.prepared();
  const auto& b = descriptors2.prepared();
  if (a.kernel != b.kernel) Fail("descriptors prepared for different matching kernels");
  internal::NearestNeighbors nn;
  if (a.kernel == internal::NnKernel::kAvx512Vnni) {
    internal::FindNearestNeighborsAvx512Vnni(a, b, &nn);
  } else {
    internal::FindNearestNeighborsGeneric(a, b, &nn);
  }
  FeatureMatches matches;
  for (int i = 0; i < a.num; ++i) {
    const int j = nn.row_best[i];
    if (j < 0 || !PassesRatioTest(nn.row_best_score[i], nn.row_second_score[i], options)) continue;
    if (options.cross_check &&
        (nn.col_best[j] != i ||
         !PassesRatioTest(nn.col_best_score[j], nn.col_second_score[j], options))) {
      continue;
    }
    matches.push_back({static_cast<point2D_t>(i), static_cast<point2D_t>(j)});
  }
  return matches;
}

FeatureMatches MatchDescriptors(const FeatureDescriptors& descriptors1,
                                const FeatureDescriptors& descriptors2,
                                const DescriptorMatchOptions& options) {
  return MatchDescriptors(MatchableDescriptors(descriptors1, options.use_simd),
                          MatchableDescriptors(descriptors2, options.use_simd), options);
}

void DescriptorMatchOptions::Check() const {
  CheckInHalfOpenRange("--ratio", max_ratio, 0, 1);
  CheckPositive("max_distance", max_distance);
}

}  // namespace varsfm
