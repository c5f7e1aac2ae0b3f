#include "varsfm/util/usable_memory.h"

#include <gtest/gtest.h>

namespace varsfm {
namespace {

TEST(UsableMemory, IsKnownOnLinux) { EXPECT_GT(UsableMemoryBytes(), size_t{0}); }

TEST(UsableMemory, CgroupFilesStateALimitOrNone) {
  EXPECT_EQ(ParseCgroupMemoryLimit("1073741824\n"), size_t{1} << 30);  // v1 and v2
  EXPECT_EQ(ParseCgroupMemoryLimit("max\n"), 0u);                      // v2: no limit
  EXPECT_EQ(ParseCgroupMemoryLimit("9223372036854771712"),
            size_t{9223372036854771712u});  // v1's "no limit", above any machine's memory
  EXPECT_EQ(ParseCgroupMemoryLimit(""), 0u);
  EXPECT_EQ(ParseCgroupMemoryLimit("12 MB"), 0u);
  EXPECT_EQ(ParseCgroupMemoryLimit("-1"), 0u);
}

}  // namespace
}  // namespace varsfm
