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

std::string ReadText(const std::filesystem::path& path) {
  std::ifstream file(path);
  if (!file) return {};
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

bool NamesMemoryController(std::string_view controllers) {
  while (!controllers.empty()) {
    const size_t comma = controllers.find(',');
    if (controllers.substr(0, comma) == "memory") return true;
    if (comma == std::string_view::npos) break;
    controllers.remove_prefix(comma + 1);
  }
  return false;
}

// The lowest limit `file_name` states in `group` (relative to `mount`) and its parents, up to
// and including the mount's root.
size_t LowestLimitUpFrom(const std::filesystem::path& mount, std::filesystem::path group,
                         const char* file_name) {
  size_t lowest = 0;
  while (true) {
    const size_t limit = ParseCgroupMemoryLimit(ReadText(mount / group / file_name));
    if (limit > 0) lowest = lowest > 0 ? std::min(lowest, limit) : limit;
    if (group.empty() || group == group.parent_path()) break;
    group = group.parent_path();
  }
  return lowest;
}

}  // namespace

size_t ParseCgroupMemoryLimit(std::string_view text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.remove_suffix(1);
  size_t bytes = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), bytes);
  if (error != std::errc() || end != text.data() + text.size()) return 0;
  return bytes;
}

size_t CgroupMemoryLimit(const std::filesystem::path& cgroup_root, std::string_view own_cgroups) {
  // Each line: hierarchy-id:controllers:path. The root is searched even where the file names no
  // group, as a container without its own cgroup namespace sees its limit there.
  std::filesystem::path v2_group, v1_group;
  std::istringstream lines{std::string(own_cgroups)};
  for (std::string line; std::getline(lines, line);) {
    const size_t first = line.find(':'), second = line.find(':', first + 1);
    if (first == std::string::npos || second == std::string::npos) continue;
    const std::string_view controllers =
        std::string_view(line).substr(first + 1, second - first - 1);
    // Relative, so that joining it to the mount appends rather than replaces. A group outside
    // the process's cgroup namespace shows as "/../..": only the mount's root is searched then.
    std::filesystem::path group = std::filesystem::path(line.substr(second + 1)).relative_path();
    if (std::find(group.begin(), group.end(), "..") != group.end()) group.clear();
    if (line.compare(0, first, "0") == 0 && controllers.empty()) v2_group = group;
    if (NamesMemoryController(controllers)) v1_group = group;
  }
  const size_t v2 = LowestLimitUpFrom(cgroup_root, v2_group, "memory.max");
  const size_t v1 = LowestLimitUpFrom(cgroup_root / "memory", v1_group, "memory.limit_in_bytes");
  if (v2 == 0 || v1 == 0) return std::max(v2, v1);
  return std::min(v2, v1);
}

size_t UsableMemoryBytes() {
  const size_t physical = PhysicalMemoryBytes();
  const size_t limit = CgroupMemoryLimit("/sys/fs/cgroup", ReadText("/proc/self/cgroup"));
  if (physical == 0) return limit;
  // An unlimited cgroup v1 states a number near 2^63, above any machine's memory.
  return limit > 0 ? std::min(physical, limit) : physical;
}

}  // namespace varsfm
