#include "varsfm/util/path_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <map>
#include <mutex>
#include <utility>

#include "varsfm/util/error.h"
#include "varsfm/util/log.h"
#include "varsfm/util/new_folder.h"

namespace varsfm {
namespace {

// The paths this process holds: descriptor and how many PathLocks share it.
struct HeldLock {
  int fd = -1;
  int count = 0;
};
std::mutex held_mutex;
std::map<std::string, HeldLock>& HeldLocks() {
  static std::map<std::string, HeldLock> held;
  return held;
}

}  // namespace

PathLock::PathLock(const std::filesystem::path& path, LockMode mode) {
  std::error_code ec;
  key_ = std::filesystem::canonical(path, ec).string();
  if (ec) Fail("cannot lock {}: {}", path.string(), ec.message());
  const bool folder = std::filesystem::is_directory(key_, ec);
  const std::lock_guard<std::mutex> guard(held_mutex);
  HeldLock& held = HeldLocks()[key_];
  if (held.count > 0) {  // this process holds it already (run, and the stage it calls)
    ++held.count;
    return;
  }
  int fd = ::open(key_.c_str(), O_RDONLY | O_CLOEXEC | (folder ? O_DIRECTORY : 0));
  const int operation = (mode == LockMode::kShared ? LOCK_SH : LOCK_EX) | LOCK_NB;
  const int error = fd < 0 ? errno : ::flock(fd, operation) != 0 ? errno : 0;
  if (error == EWOULDBLOCK) {
    ::close(fd);
    HeldLocks().erase(key_);
    Fail("{} is in use by another varsfm command: wait for it to end, or give another {}",
         path.string(), folder ? "folder" : "workspace");
  }
  if (error != 0) {
    // A file system without locks (some network and FUSE mounts): the command still runs, as it
    // did before the lock existed; only a second one at once goes unnoticed.
    if (fd >= 0) ::close(fd);
    fd = -1;
    warn(
        "cannot lock {} ({}): another varsfm command writing there at once would not be "
        "noticed",
        path.string(), std::strerror(error));
  }
  held = {fd, 1};
}

PathLock::~PathLock() {
  const std::lock_guard<std::mutex> guard(held_mutex);
  auto it = HeldLocks().find(key_);
  if (it == HeldLocks().end() || --it->second.count > 0) return;
  if (it->second.fd >= 0) ::close(it->second.fd);  // releases the flock
  HeldLocks().erase(it);
}

OutputFolderLock::OutputFolderLock(std::filesystem::path output) : output_(std::move(output)) {
  std::error_code ec;
  if (std::filesystem::is_directory(output_, ec)) lock_.emplace(output_);
}

void OutputFolderLock::CreateAndLock() {
  CreateFolder(output_);
  if (!lock_) lock_.emplace(output_);
}

}  // namespace varsfm
