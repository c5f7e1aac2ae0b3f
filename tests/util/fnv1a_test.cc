#include "varsfm/util/fnv1a.h"

#include <gtest/gtest.h>

namespace varsfm {
namespace {

// The published FNV-1a 64-bit test vectors, and a hash continued over a second piece.
TEST(Fnv1a, MatchesTheReferenceValues) {
  EXPECT_EQ(Fnv1a("", 0), 0xcbf29ce484222325ull);
  EXPECT_EQ(Fnv1a("a", 1), 0xaf63dc4c8601ec8cull);
  EXPECT_EQ(Fnv1a("foobar", 6), 0x85944171f73967e8ull);
  EXPECT_EQ(Fnv1a("bar", 3, Fnv1a("foo", 3)), 0x85944171f73967e8ull);
}

}  // namespace
}  // namespace varsfm
