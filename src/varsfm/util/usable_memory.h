#pragma once
// The machine's memory, for the defaults of the stages that bound what they hold at once.
#include <cstddef>
#include <string_view>

namespace varsfm {

// Physical memory in bytes, or the memory limit of the process's control group (a container's
// limit: cgroup v2 memory.max, v1 memory.limit_in_bytes) where it is lower; 0 where the system
// says neither.
size_t UsableMemoryBytes();

// The limit a cgroup memory file states, in bytes; 0 for none ("max", or text that is not a
// number).
size_t ParseCgroupMemoryLimit(std::string_view text);

}  // namespace varsfm
