#include "varsfm/util/usable_memory.h"

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <fstream>
#include <sstream>
#include <string>

namespace varsfm {
namespace {

size_t PhysicalMemoryBytes() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page_size = sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page_size <= 0) return 0;
  return static_cast<size_t>(pages) * static_cast<size_t>(page_size);
}

// A container sees its own control group at the root of the cgroup mount.
size_t CgroupMemoryLimit() {
  for (const char* path :
       {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
    std::ifstream file(path);
    if (!file) continue;
    std::stringstream text;
    text << file.rdbuf();
    return ParseCgroupMemoryLimit(text.str());
  }
  return 0;
}

}  // namespace

size_t ParseCgroupMemoryLimit(std::string_view text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.remove_suffix(1);
  size_t bytes = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), bytes);
  if (error != std::errc() || end != text.data() + text.size()) return 0;
  return bytes;
}

size_t UsableMemoryBytes() {
  const size_t physical = PhysicalMemoryBytes(), limit = CgroupMemoryLimit();
  if (physical == 0) return limit;
  // An unlimited cgroup v1 states a number near 2^63, above any machine's memory.
  return limit > 0 ? std::min(physical, limit) : physical;
}

}  // namespace varsfm
