#include "varsfm/matching/descriptor_matcher.h"

#include <algorithm>
#include <numeric>
#include <random>

#include <gtest/gtest.h>

#include "varsfm/matching/nearest_neighbors.h"

namespace varsfm {
namespace {

// SIFT-like descriptors: non-negative, mostly small values with a few large ones, so unrelated
// descriptors are far apart (angles around 0.9 rad) as real ones are.
FeatureDescriptors RandomDescriptors(int n, std::mt19937& rng) {
  FeatureDescriptors d(n, 128);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < 128; ++k) d(i, k) = static_cast<uint8_t>(std::pow(u(rng), 3) * 255);
  }
  return d;
}

// A copy of `row` with every byte moved by up to +-noise.
Eigen::Matrix<uint8_t, 1, 128> Perturb(const auto& row, int noise, std::mt19937& rng) {
  std::uniform_int_distribution<int> u(-noise, noise);
  Eigen::Matrix<uint8_t, 1, 128> out;
  for (int k = 0; k < 128; ++k) out(k) = static_cast<uint8_t>(std::clamp(row(k) + u(rng), 0, 255));
  return out;
}

TEST(DescriptorMatcher, RecoversKnownCorrespondences) {
  std::mt19937 rng(1);
  const FeatureDescriptors d2 = RandomDescriptors(700, rng);
  // Image 1 sees 300 of image 2's features, shuffled and slightly perturbed, plus 200 others.
  std::vector<int> truth(700);
  std::iota(truth.begin(), truth.end(), 0);
  std::shuffle(truth.begin(), truth.end(), rng);
  truth.resize(300);
  FeatureDescriptors d1 = RandomDescriptors(500, rng);
  for (int i = 0; i < 300; ++i) d1.row(i) = Perturb(d2.row(truth[i]), 6, rng);

  const FeatureMatches matches = MatchDescriptors(d1, d2);
  ASSERT_EQ(matches.size(), 300u);
  for (int i = 0; i < 300; ++i) {
    EXPECT_EQ(matches[i].point2D_idx1, static_cast<point2D_t>(i));
    EXPECT_EQ(matches[i].point2D_idx2, static_cast<point2D_t>(truth[i]));
  }
}

TEST(DescriptorMatcher, RatioTestRejectsAmbiguousMatches) {
  std::mt19937 rng(2);
  FeatureDescriptors d2 = RandomDescriptors(100, rng);
  // Descriptor 0 of image 2 has a near twin (descriptor 1); image 1 sees a noisier version of
  // it, about as close to both: ambiguous.
  d2.row(1) = Perturb(d2.row(0), 2, rng);
  FeatureDescriptors d1(2, 128);
  d1.row(0) = Perturb(d2.row(0), 12, rng);
  d1.row(1) = d2.row(50);
  const FeatureMatches matches = MatchDescriptors(d1, d2);
  ASSERT_EQ(matches.size(), 1u);
  EXPECT_EQ(matches[0], (FeatureMatch{1, 50}));

  // Without the ratio test (ratio 1 accepts any strictly better best) both are kept.
  DescriptorMatchOptions loose;
  loose.max_ratio = 1.0;
  loose.cross_check = false;
  EXPECT_EQ(MatchDescriptors(d1, d2, loose).size(), 2u);
}

TEST(DescriptorMatcher, CrossCheckKeepsOnlyMutualNearestNeighbours) {
  std::mt19937 rng(3);
  FeatureDescriptors d2 = RandomDescriptors(100, rng);
  // Both descriptors of image 1 are nearest to image 2's descriptor 7, the first exactly, the
  // second clearly but less so; only the first is 7's nearest neighbour in return.
  FeatureDescriptors d1(2, 128);
  d1.row(0) = d2.row(7);
  d1.row(1) = Perturb(d2.row(7), 40, rng);
  DescriptorMatchOptions one_way;
  one_way.cross_check = false;
  const FeatureMatches without = MatchDescriptors(d1, d2, one_way);
  ASSERT_EQ(without.size(), 2u);
  EXPECT_EQ(without[1], (FeatureMatch{1, 7}));
  const FeatureMatches with = MatchDescriptors(d1, d2);
  ASSERT_EQ(with.size(), 1u);
  EXPECT_EQ(with[0], (FeatureMatch{0, 7}));
}

TEST(DescriptorMatcher, MaxDistanceRejectsUnrelatedDescriptors) {
  std::mt19937 rng(4);
  const FeatureDescriptors d1 = RandomDescriptors(50, rng);
  const FeatureDescriptors d2 = RandomDescriptors(60, rng);
  DescriptorMatchOptions options;
  options.max_distance = 0.3;  // unrelated SIFT-like vectors are much further apart
  EXPECT_TRUE(MatchDescriptors(d1, d2, options).empty());
  EXPECT_TRUE(MatchDescriptors(FeatureDescriptors(0, 128), d2).empty());
  EXPECT_TRUE(MatchDescriptors(d1, FeatureDescriptors(0, 128)).empty());
}

TEST(DescriptorMatcher, SimdKernelEqualsGenericKernel) {
  if (!internal::CpuHasAvx512Vnni()) GTEST_SKIP() << "CPU without AVX-512 VNNI";
  std::mt19937 rng(5);
  // Sizes that are not multiples of the kernel's 8 x 32 tiles; some shared features.
  const FeatureDescriptors d2 = RandomDescriptors(517, rng);
  FeatureDescriptors d1 = RandomDescriptors(301, rng);
  for (int i = 0; i < 150; ++i) d1.row(i) = Perturb(d2.row(3 * i), 30, rng);
  d1.row(200).setZero();  // a zero descriptor must not break either kernel

  using internal::NnKernel;
  internal::NearestNeighbors generic, simd;
  internal::FindNearestNeighborsGeneric(internal::PrepareDescriptors(d1, NnKernel::kGeneric),
                                        internal::PrepareDescriptors(d2, NnKernel::kGeneric),
                                        &generic);
  internal::FindNearestNeighborsAvx512Vnni(internal::PrepareDescriptors(d1, NnKernel::kAvx512Vnni),
                                           internal::PrepareDescriptors(d2, NnKernel::kAvx512Vnni),
                                           &simd);
  EXPECT_EQ(generic.row_best, simd.row_best);
  EXPECT_EQ(generic.row_best_score, simd.row_best_score);
  EXPECT_EQ(generic.row_second_score, simd.row_second_score);
  EXPECT_EQ(generic.col_best, simd.col_best);
  EXPECT_EQ(generic.col_best_score, simd.col_best_score);
  EXPECT_EQ(generic.col_second_score, simd.col_second_score);

  DescriptorMatchOptions generic_options;
  generic_options.use_simd = false;
  const FeatureMatches expected = MatchDescriptors(d1, d2, generic_options);
  EXPECT_GT(expected.size(), 100u);
  EXPECT_EQ(MatchDescriptors(d1, d2), expected);
}

}  // namespace
}  // namespace varsfm
