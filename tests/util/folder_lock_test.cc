#include "varsfm/util/folder_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

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
  explicit ForeignHolder(const fs::path& folder)
      : fd_(::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC)) {}
  ~ForeignHolder() { Release(); }
  bool Lock() { return ::flock(fd_, LOCK_EX | LOCK_NB) == 0; }
  void Release() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

 private:
  int fd_;
};

TEST(FolderLock, SecondHolderIsRefusedWithOneLineNamingTheFolder) {
  testing::TempDir tmp("folder_lock");
  ForeignHolder other(tmp.path());
  ASSERT_TRUE(other.Lock());
  try {
    FolderLock lock(tmp.path());
    ADD_FAILURE() << "a folder another command holds was locked";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(tmp.path().string()), std::string::npos) << message;
    EXPECT_NE(message.find("in use by another varsfm command"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  other.Release();
  FolderLock lock(tmp.path());  // free again
}

TEST(FolderLock, ReentrantWithinOneProcessAndReleasedByTheLastHolder) {
  testing::TempDir tmp("folder_lock_nested");
  {
    const FolderLock outer(tmp.path());
    {
      const FolderLock inner(tmp.path() / "." / "");  // the same folder, spelled otherwise
      EXPECT_FALSE(ForeignHolder(tmp.path()).Lock());
    }
    EXPECT_FALSE(ForeignHolder(tmp.path()).Lock());  // the outer lock still holds
  }
  EXPECT_TRUE(ForeignHolder(tmp.path()).Lock());
}

// The lock is the kernel's: a process that dies holding it leaves nothing stale behind.
TEST(FolderLock, ReleasedWhenTheHoldingProcessDies) {
  testing::TempDir tmp("folder_lock_child");
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const FolderLock lock(tmp.path());
    ::_exit(ForeignHolder(tmp.path()).Lock() ? 1 : 0);  // dies holding it
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  const FolderLock lock(tmp.path());
  EXPECT_TRUE(fs::is_empty(tmp.path()));  // nothing written into the folder
}

TEST(FolderLock, MissingFolderIsAnError) {
  testing::TempDir tmp("folder_lock_missing");
  EXPECT_THROW(FolderLock(tmp.path() / "absent"), Error);
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

TEST(WorkspaceFolder, BareFileNameLiesInTheCurrentFolder) {
  EXPECT_EQ(WorkspaceFolder("workspace.db"), fs::path("."));
  EXPECT_EQ(WorkspaceFolder("out/workspace.db"), fs::path("out"));
}

}  // namespace
}  // namespace varsfm
