#pragma once
// Memory for arrays that together may outgrow the machine's RAM (a thousand views' depth maps
// and photos): pages of an unnamed file in a scratch folder, mapped shared. The kernel writes
// such pages out and drops them under memory pressure, and reads them back when they are
// touched, so what a stage holds is bounded by the disk, not by RAM, with no swap configured.
// The file has no name (O_TMPFILE; otherwise it is unlinked at once): it leaves nothing in the
// folder, also when the process is killed, and vanishes with its last mapping.
#include <cstddef>
#include <filesystem>
#include <memory>
#include <string_view>

namespace varsfm {

class ScratchMemory {
 public:
  // `bytes` (at least one) of zeroed memory backed by an unnamed file in `folder`, its blocks
  // reserved up front. Throws varsfm::Error, one line naming the folder, when the file cannot
  // be made or the disk has no room: a full disk is an error here, not a crash (SIGBUS) at the
  // first write into a page the file could not back.
  static std::shared_ptr<ScratchMemory> Create(const std::filesystem::path& folder, size_t bytes);

  ScratchMemory(const ScratchMemory&) = delete;
  ScratchMemory& operator=(const ScratchMemory&) = delete;
  ~ScratchMemory();

  void* data() const { return data_; }
  size_t size() const { return size_; }

 private:
  ScratchMemory(void* data, size_t size) : data_(data), size_(size) {}
  void* data_;
  size_t size_;
};

// Whether `folder` can hold scratch memory now; where it cannot (missing, read-only, full), a
// warning says so and that `what` stays in RAM: a run that would have fit in RAM still runs.
bool ScratchFolderUsable(const std::filesystem::path& folder, std::string_view what);

// The existing folder nearest to `path` (itself, or its nearest existing parent; the current
// folder for a relative path none of whose parents exist): where a stage that has not created
// its output folder yet can keep its scratch memory on the same disk.
std::filesystem::path NearestExistingFolder(const std::filesystem::path& path);

}  // namespace varsfm
