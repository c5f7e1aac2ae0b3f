#include "varsfm/util/scratch_memory.h"

#include <cstdint>
#include <string>

#include <gtest/gtest.h>

#include "support/test_data.h"
#include "varsfm/util/error.h"
#include "varsfm/util/scratch_array.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;

bool IsEmptyFolder(const fs::path& dir) {
  return fs::directory_iterator(dir) == fs::directory_iterator();
}

TEST(ScratchMemory, ZeroedWritableAndLeavesNoFileBehind) {
  testing::TempDir tmp("scratch_memory");
  {
    const std::shared_ptr<ScratchMemory> memory = ScratchMemory::Create(tmp.path(), 3 << 20);
    ASSERT_EQ(memory->size(), size_t{3} << 20);
    auto* bytes = static_cast<uint8_t*>(memory->data());
    size_t nonzero = 0;
    for (size_t i = 0; i < memory->size(); ++i) nonzero += bytes[i] != 0;
    EXPECT_EQ(nonzero, 0u);
    for (size_t i = 0; i < memory->size(); ++i) bytes[i] = static_cast<uint8_t>(i * 7);
    size_t wrong = 0;
    for (size_t i = 0; i < memory->size(); ++i) wrong += bytes[i] != static_cast<uint8_t>(i * 7);
    EXPECT_EQ(wrong, 0u);
    // The file has no name: the folder looks as it did, also while the memory is in use.
    EXPECT_TRUE(IsEmptyFolder(tmp.path()));
  }
  EXPECT_TRUE(IsEmptyFolder(tmp.path()));
}

TEST(ScratchMemory, AMissingFolderIsAnErrorNamingIt) {
  testing::TempDir tmp("scratch_memory_missing");
  const fs::path missing = tmp.path() / "not-there";
  try {
    ScratchMemory::Create(missing, 4096);
    ADD_FAILURE() << "scratch memory in a missing folder";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(missing.string()), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  EXPECT_FALSE(fs::exists(missing));
}

TEST(ScratchMemory, AFolderThatCannotHoldItIsSaidToBeUnusable) {
  testing::TempDir tmp("scratch_memory_usable");
  EXPECT_TRUE(ScratchFolderUsable(tmp.path(), "test arrays"));
  EXPECT_FALSE(ScratchFolderUsable(tmp.path() / "not-there", "test arrays"));
  EXPECT_TRUE(fs::directory_iterator(tmp.path()) == fs::directory_iterator());
}

TEST(ScratchMemory, NearestExistingFolder) {
  testing::TempDir tmp("scratch_memory_nearest");
  EXPECT_EQ(NearestExistingFolder(tmp.path()), tmp.path());
  EXPECT_EQ(NearestExistingFolder(tmp.path() / "a" / "b"), tmp.path());
  EXPECT_FALSE(fs::exists(tmp.path() / "a"));
}

TEST(ScratchArray, KeepsItsElementsWhenMovedToScratchMemory) {
  testing::TempDir tmp("scratch_array");
  ScratchArray<float> a, b;
  a.assign(1000, 0.0f);
  b.assign(3, 2.0f);
  for (size_t i = 0; i < a.size(); ++i) a[i] = static_cast<float>(i) / 3;
  const ScratchArray<float> heap = a;
  EXPECT_FALSE(a.InScratch());

  ScratchLayout layout;
  layout.Add(a.size() * sizeof(float), alignof(float));
  layout.Add(b.size() * sizeof(float), alignof(float));
  const std::shared_ptr<ScratchMemory> memory = ScratchMemory::Create(tmp.path(), layout.bytes);
  a.MoveTo(memory, layout.offsets[0]);
  b.MoveTo(memory, layout.offsets[1]);
  ASSERT_TRUE(a.InScratch());
  EXPECT_EQ(a, heap);
  EXPECT_EQ(b.size(), 3u);
  EXPECT_EQ(b[2], 2.0f);
  EXPECT_EQ(static_cast<void*>(a.data()), memory->data());

  // Writes land in the scratch memory; a copy is on the heap and independent of it.
  a[5] = -1;
  ScratchArray<float> copy = a;
  EXPECT_FALSE(copy.InScratch());
  copy[5] = 7;
  EXPECT_EQ(a[5], -1.0f);

  // A moved array takes the memory along and leaves an empty one.
  ScratchArray<float> moved = std::move(a);
  EXPECT_TRUE(moved.InScratch());
  EXPECT_EQ(moved.size(), 1000u);
  EXPECT_TRUE(a.empty());  // NOLINT(bugprone-use-after-move): the moved-from state is specified
  EXPECT_EQ(moved[5], -1.0f);

  // assign puts it back on the heap.
  moved.assign(2, 1.0f);
  EXPECT_FALSE(moved.InScratch());
  EXPECT_EQ(moved.size(), 2u);
}

TEST(ScratchLayout, AlignsEachArray) {
  ScratchLayout layout;
  layout.Add(3, 1);
  layout.Add(8, 4);
  layout.Add(12, 4);
  ASSERT_EQ(layout.offsets.size(), 3u);
  EXPECT_EQ(layout.offsets[0], 0u);
  EXPECT_EQ(layout.offsets[1], 4u);
  EXPECT_EQ(layout.offsets[2], 12u);
  EXPECT_EQ(layout.bytes, 24u);
}

}  // namespace
}  // namespace varsfm
