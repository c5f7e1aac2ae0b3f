#include "varsfm/util/usable_memory.h"

#include <fstream>

#include <gtest/gtest.h>

#include "support/test_data.h"

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

void WriteLimit(const std::filesystem::path& folder, const char* file, const char* text) {
  std::filesystem::create_directories(folder);
  std::ofstream(folder / file) << text;
}

TEST(UsableMemory, TheProcessOwnGroupAndItsParentsBindIt) {
  testing::TempDir tmp("cgroup_limits");
  const std::filesystem::path root = tmp.path();
  // cgroup v1: the root unlimited, a parent at 2 GiB, the process's own group at 600 MiB.
  WriteLimit(root / "memory", "memory.limit_in_bytes", "9223372036854771712\n");
  WriteLimit(root / "memory/runner", "memory.limit_in_bytes", "2147483648\n");
  WriteLimit(root / "memory/runner/job", "memory.limit_in_bytes", "629145600\n");
  EXPECT_EQ(CgroupMemoryLimit(root, "4:memory:/runner/job\n0::/\n"), size_t{600} << 20);
  // The limit on a parent binds a group that states none; controllers may share a hierarchy.
  WriteLimit(root / "memory/runner/free", "memory.limit_in_bytes", "9223372036854771712\n");
  EXPECT_EQ(CgroupMemoryLimit(root, "3:cpu,memory:/runner/free\n"), size_t{2} << 30);
  // A group the mount does not show (a container seeing its own group at the root).
  EXPECT_EQ(CgroupMemoryLimit(root, "4:memory:/host/only/path\n"), 9223372036854771712u);
  // A group outside the process's cgroup namespace: the root only.
  EXPECT_EQ(CgroupMemoryLimit(root, "4:memory:/../runner/job\n"), 9223372036854771712u);
  // cgroup v2: memory.max in the unified tree, "max" meaning none.
  WriteLimit(root, "memory.max", "max\n");
  WriteLimit(root / "user.slice", "memory.max", "1073741824\n");
  WriteLimit(root / "user.slice/run.scope", "memory.max", "max\n");
  EXPECT_EQ(CgroupMemoryLimit(root, "0::/user.slice/run.scope\n"), size_t{1} << 30);
  // Both hierarchies: the lower limit.
  EXPECT_EQ(CgroupMemoryLimit(root, "4:memory:/runner/job\n0::/user.slice/run.scope\n"),
            size_t{600} << 20);
  // No file at all: no limit.
  EXPECT_EQ(CgroupMemoryLimit(root / "missing", "0::/\n"), 0u);
}

}  // namespace
}  // namespace varsfm
