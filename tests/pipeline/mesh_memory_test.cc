// The mesh stage's cap on merged points, from the memory it may use.
#include <gtest/gtest.h>

#include "varsfm/pipeline/mesh.h"

namespace varsfm {
namespace {

TEST(MeshMemory, MergedPointsFitTheMemoryLeftBesideTheCloud) {
  const size_t gib = size_t{1} << 30;
  // 4 GiB, a cloud of 2 M points (~0.5 GB): the rest at ~1.5 KB a merged point.
  EXPECT_EQ(MergedPointsWithin(4 * gib, 2'000'000),
            (4 * gib - 2'000'000 * kBytesPerInputPoint) / kBytesPerMergedPoint);
  // The more the cloud takes, the fewer merged points.
  EXPECT_LT(MergedPointsWithin(4 * gib, 8'000'000), MergedPointsWithin(4 * gib, 2'000'000));
  // Never below the floor, also where the cloud alone is beyond the memory.
  EXPECT_EQ(MergedPointsWithin(gib / 16, 0), kMinMergedPoints);
  EXPECT_EQ(MergedPointsWithin(gib, 100'000'000), kMinMergedPoints);
}

}  // namespace
}  // namespace varsfm
