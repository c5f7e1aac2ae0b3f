#include "varsfm/util/heap_policy.h"

#include <cstdlib>
#include <cstring>

#include <gtest/gtest.h>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace varsfm {
namespace {

#if defined(__GLIBC__)
// Under the policy a block far above glibc's largest mmap threshold (32 MB) comes from the heap,
// not from a mapping of its own, and stays in the heap when freed: the next one reuses it.
TEST(HeapPolicy, LargeBlocksComeFromTheHeapAndStayThere) {
  KeepFreedMemoryForReuse();
  constexpr size_t kSize = 96u << 20;
  const size_t mapped_before = mallinfo2().hblkhd;  // blocks other tests left mapped
  auto* block = static_cast<char*>(std::malloc(kSize));
  ASSERT_NE(block, nullptr);
  std::memset(block, 1, kSize);
  EXPECT_EQ(mallinfo2().hblkhd, mapped_before);  // no new mmapped block
  std::free(block);
  const size_t heap_after_free = mallinfo2().arena;
  EXPECT_GE(heap_after_free, kSize);  // not trimmed back to the kernel
  auto* again = static_cast<char*>(std::malloc(kSize));
  ASSERT_NE(again, nullptr);
  EXPECT_EQ(mallinfo2().arena, heap_after_free);  // served from what was kept
  std::free(again);
}
#endif

}  // namespace
}  // namespace varsfm
