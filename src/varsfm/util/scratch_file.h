#pragma once
// A file with no name that a stage appends records to and reads back once, for outputs that may
// outgrow RAM before their size is known (a dense cloud of tens of millions of points, whose
// PLY header needs the count before the first record). Like scratch memory
// (util/scratch_memory.h), it leaves nothing in its folder, also when the process is killed.
#include <cstddef>
#include <filesystem>
#include <ostream>
#include <vector>

namespace varsfm {

// An unnamed file in `folder` opened for reading and writing (O_TMPFILE where the file system
// supports it, else a named file unlinked at once); -1 with errno set where it cannot be made.
int OpenUnnamedFile(const std::filesystem::path& folder);

class ScratchFile {
 public:
  // Throws varsfm::Error, one line naming `folder`, when the file cannot be made.
  explicit ScratchFile(const std::filesystem::path& folder);
  ~ScratchFile();
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;

  // Buffered; throws varsfm::Error when the disk refuses the bytes (full, ...).
  void Append(const void* data, size_t size);
  size_t size() const { return written_ + buffer_.size(); }
  // Writes everything appended so far to `out`, from the first byte. Throws varsfm::Error when
  // the file cannot be read back.
  void CopyTo(std::ostream& out);

 private:
  void Flush();

  std::filesystem::path folder_;  // for the error lines
  int fd_ = -1;
  size_t written_ = 0;
  std::vector<char> buffer_;
};

}  // namespace varsfm
