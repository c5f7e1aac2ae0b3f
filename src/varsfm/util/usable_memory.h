#pragma once
// The machine's memory, for the defaults of the stages that bound what they hold at once.
#include <cstddef>
#include <filesystem>
#include <string_view>

namespace varsfm {

// Physical memory in bytes, or the memory limit of the process's control group (a container's
// limit: cgroup v2 memory.max, v1 memory.limit_in_bytes) where it is lower; 0 where the system
// says neither.
size_t UsableMemoryBytes();

// The lowest memory limit on the way from the process's own control group up to the root of
// the cgroup mount `cgroup_root` (/sys/fs/cgroup), in bytes; 0 for none. `own_cgroups` is the
// text of /proc/self/cgroup: "0::/path" names the group under cgroup v2, "N:memory:/path" under
// v1's memory controller (mounted at cgroup_root/memory). A group's limit binds every group
// below it, so a process limited by a parent (`systemd-run -p MemoryMax`, a container runtime's
// slice) is found as well as one limited by its own group. Groups missing under the mount (a
// container that sees only its own group at the root) are passed over.
size_t CgroupMemoryLimit(const std::filesystem::path& cgroup_root, std::string_view own_cgroups);

// The limit a cgroup memory file states, in bytes; 0 for none ("max", or text that is not a
// number).
size_t ParseCgroupMemoryLimit(std::string_view text);

}  // namespace varsfm
