#include "varsfm/util/path_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "support/test_data.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;

// Another holder of the folder's lock: flock on a descriptor of its own is what another process
// holds (flock locks belong to an open file description, so this conflicts within one process).
class ForeignHolder {
 public:
  explicit ForeignHolder(const fs::path& path) : fd_(::open(path.c_str(), O_RDONLY | O_CLOEXEC)) {}
  ~ForeignHolder() { Release(); }
  bool Lock() { return ::flock(fd_, LOCK_EX | LOCK_NB) == 0; }
  bool LockShared() { return ::flock(fd_, LOCK_SH | LOCK_NB) == 0; }
  void Release() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

 private:
  int fd_;
};

TEST(PathLock, SecondHolderIsRefusedWithOneLineNamingTheFolder) {
  testing::TempDir tmp("folder_lock");
  ForeignHolder other(tmp.path());
  ASSERT_TRUE(other.Lock());
  try {
    PathLock lock(tmp.path());
    ADD_FAILURE() << "a folder another command holds was locked";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(tmp.path().string()), std::string::npos) << message;
    EXPECT_NE(message.find("in use by another varsfm command"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  other.Release();
  PathLock lock(tmp.path());  // free again
}

TEST(PathLock, ReentrantWithinOneProcessAndReleasedByTheLastHolder) {
  testing::TempDir tmp("folder_lock_nested");
  {
    const PathLock outer(tmp.path());
    {
      const PathLock inner(tmp.path() / "." / "");  // the same folder, spelled otherwise
      EXPECT_FALSE(ForeignHolder(tmp.path()).Lock());
    }
    EXPECT_FALSE(ForeignHolder(tmp.path()).Lock());  // the outer lock still holds
  }
  EXPECT_TRUE(ForeignHolder(tmp.path()).Lock());
}

// The lock is the kernel's: a process that dies holding it leaves nothing stale behind.
TEST(PathLock, ReleasedWhenTheHoldingProcessDies) {
  testing::TempDir tmp("folder_lock_child");
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const PathLock lock(tmp.path());
    ::_exit(ForeignHolder(tmp.path()).Lock() ? 1 : 0);  // dies holding it
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  const PathLock lock(tmp.path());
  EXPECT_TRUE(fs::is_empty(tmp.path()));  // nothing written into the folder
}

TEST(PathLock, MissingFolderIsAnError) {
  testing::TempDir tmp("folder_lock_missing");
  EXPECT_THROW(PathLock(tmp.path() / "absent"), Error);
}

TEST(OutputFolderLock, LocksAnExistingFolderAtOnceAndANewOneWhenCreated) {
  testing::TempDir tmp("output_folder_lock");
  {
    const OutputFolderLock existing(tmp.path());
    EXPECT_FALSE(ForeignHolder(tmp.path()).Lock());
  }
  const fs::path created = tmp.path() / "out" / "deeper";
  OutputFolderLock lock(created);
  EXPECT_FALSE(fs::exists(created));
  lock.CreateAndLock();
  EXPECT_TRUE(fs::is_directory(created));
  EXPECT_FALSE(ForeignHolder(created).Lock());
  lock.CreateAndLock();  // again: nothing more to do
}

// A workspace is locked as a file: exclusive for a command that writes it, shared for one that
// reads it (several maps of one workspace at once, but no match while one runs).
TEST(PathLock, AWorkspaceFileIsLockedExclusiveOrShared) {
  testing::TempDir tmp("path_lock_file");
  const fs::path workspace = tmp.path() / "workspace.db";
  std::ofstream(workspace) << "x";
  {
    const PathLock reading(workspace, LockMode::kShared);
    EXPECT_TRUE(ForeignHolder(workspace).LockShared());  // another reader
    EXPECT_FALSE(ForeignHolder(workspace).Lock());       // no writer
  }
  ForeignHolder reader(workspace);
  ASSERT_TRUE(reader.LockShared());
  try {
    PathLock writing(workspace);
    ADD_FAILURE() << "a workspace another command reads was locked for writing";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("give another workspace"), std::string::npos) << e.what();
  }
  const PathLock also_reading(workspace, LockMode::kShared);
  // Another workspace in the same folder is another lock.
  std::ofstream(tmp.path() / "other.db") << "x";
  const PathLock other(tmp.path() / "other.db");
}

}  // namespace
}  // namespace varsfm
