#include "varsfm/scene/triangle_mesh.h"

#include <gtest/gtest.h>

namespace varsfm {
namespace {

TEST(UndirectedEdgeKey, IsTheSameInEitherOrderAndTellsEdgesApart) {
  EXPECT_EQ(UndirectedEdgeKey(3, 7), UndirectedEdgeKey(7, 3));
  EXPECT_EQ(UndirectedEdgeKey(7, 3), (uint64_t{3} << 32) | 7);
  EXPECT_NE(UndirectedEdgeKey(3, 7), UndirectedEdgeKey(3, 8));
  // The largest index fills the low half without reaching the high one.
  EXPECT_EQ(UndirectedEdgeKey(UINT32_MAX, 0), uint64_t{UINT32_MAX});
  EXPECT_EQ(UndirectedEdgeKey(UINT32_MAX, 1), (uint64_t{1} << 32) | UINT32_MAX);
}

}  // namespace
}  // namespace varsfm
