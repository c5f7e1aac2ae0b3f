#include "varsfm/util/scratch_memory.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "varsfm/util/error.h"
#include "varsfm/util/log.h"
#include "varsfm/util/scratch_file.h"

namespace varsfm {

std::shared_ptr<ScratchMemory> ScratchMemory::Create(const std::filesystem::path& folder,
                                                     size_t bytes) {
  if (bytes == 0) bytes = 1;
  const int fd = OpenUnnamedFile(folder);
  if (fd < 0) Fail("cannot make scratch memory in {}: {}", folder.string(), std::strerror(errno));
  // posix_fallocate returns the error instead of setting errno.
  const int reserved = posix_fallocate(fd, 0, static_cast<off_t>(bytes));
  if (reserved != 0) {
    close(fd);
    Fail("cannot reserve {:.1f} MB of scratch memory in {}: {}", bytes / 1e6, folder.string(),
         std::strerror(reserved));
  }
  void* data = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  const int map_error = errno;
  close(fd);  // the mapping keeps the file
  if (data == MAP_FAILED)
    Fail("cannot map {:.1f} MB of scratch memory in {}: {}", bytes / 1e6, folder.string(),
         std::strerror(map_error));
  return std::shared_ptr<ScratchMemory>(new ScratchMemory(data, bytes));
}

ScratchMemory::~ScratchMemory() { munmap(data_, size_); }

bool ScratchFolderUsable(const std::filesystem::path& folder, std::string_view what) {
  try {
    ScratchMemory::Create(folder, 1);
    return true;
  } catch (const Error& e) {
    warn("{}: {} stay in RAM", e.what(), what);
    return false;
  }
}

std::filesystem::path NearestExistingFolder(const std::filesystem::path& path) {
  std::error_code error;
  for (std::filesystem::path p = path; !p.empty(); p = p.parent_path()) {
    if (std::filesystem::is_directory(p, error)) return p;
    if (p == p.parent_path()) break;
  }
  return ".";
}

}  // namespace varsfm
