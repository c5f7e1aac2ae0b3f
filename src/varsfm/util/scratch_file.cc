#include "varsfm/util/scratch_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string>

#include "varsfm/util/error.h"

namespace varsfm {
namespace {

// Large enough that the system calls cost nothing beside the records' formatting.
constexpr size_t kBufferBytes = size_t{1} << 20;

}  // namespace

int OpenUnnamedFile(const std::filesystem::path& folder) {
#ifdef O_TMPFILE
  const int fd = open(folder.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
  if (fd >= 0) return fd;
#endif
  std::string name = (folder / ".varsfm-scratch-XXXXXX").string();
  std::vector<char> buffer(name.begin(), name.end());
  buffer.push_back('\0');
  const int named = mkostemp(buffer.data(), O_CLOEXEC);
  if (named < 0) return -1;
  unlink(buffer.data());
  return named;
}

ScratchFile::ScratchFile(const std::filesystem::path& folder) : folder_(folder) {
  fd_ = OpenUnnamedFile(folder);
  if (fd_ < 0) Fail("cannot make a scratch file in {}: {}", folder.string(), std::strerror(errno));
  buffer_.reserve(kBufferBytes);
}

ScratchFile::~ScratchFile() { close(fd_); }

void ScratchFile::Append(const void* data, size_t size) {
  const char* bytes = static_cast<const char*>(data);
  while (size > 0) {
    const size_t n = std::min(size, kBufferBytes - buffer_.size());
    buffer_.insert(buffer_.end(), bytes, bytes + n);
    bytes += n;
    size -= n;
    if (buffer_.size() == kBufferBytes) Flush();
  }
}

void ScratchFile::Flush() {
  size_t done = 0;
  while (done < buffer_.size()) {
    const ssize_t n = pwrite(fd_, buffer_.data() + done, buffer_.size() - done,
                             static_cast<off_t>(written_ + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      Fail("cannot write {:.1f} MB to a scratch file in {}: {}",
           static_cast<double>(written_ + buffer_.size()) / 1e6, folder_.string(),
           n < 0 ? std::strerror(errno) : "no room");
    done += static_cast<size_t>(n);
  }
  written_ += buffer_.size();
  buffer_.clear();
}

void ScratchFile::CopyTo(std::ostream& out) {
  Flush();
  std::vector<char> chunk(kBufferBytes);
  for (size_t offset = 0; offset < written_;) {
    const ssize_t n = pread(fd_, chunk.data(), std::min(chunk.size(), written_ - offset),
                            static_cast<off_t>(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      Fail("cannot read back a scratch file in {}: {}", folder_.string(),
           n < 0 ? std::strerror(errno) : "it is shorter than written");
    out.write(chunk.data(), n);
    offset += static_cast<size_t>(n);
  }
}

}  // namespace varsfm
