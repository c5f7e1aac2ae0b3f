#pragma once
// One varsfm command at a time in a folder. Two commands writing one workspace or output folder
// at once (a second terminal, a script started twice) interleave their results: one removes
// the outputs the other has just written (RemoveOutputsAfter), both rewrite summary.json, and
// the last to finish wins file by file. A command that writes into a folder holds this lock on
// it for as long as it runs; a second one is refused at once with a one-line error.
//
// The lock is flock(2) on the folder itself, so nothing is written into the folder and no stale
// lock outlives a crashed or killed process (the kernel releases it with the process). Within
// one process the lock is re-entrant: `run` holds its output folder and calls the stages, each
// of which locks the same folder again.
#include <filesystem>
#include <optional>
#include <string>

namespace varsfm {

class FolderLock {
 public:
  // Locks `folder`, which must exist. Throws varsfm::Error when another process holds it
  // ("... is in use by another varsfm command ...") or the folder does not exist; where the file
  // system cannot lock (or the folder cannot be opened), warns and goes on unlocked.
  explicit FolderLock(const std::filesystem::path& folder);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

 private:
  std::string key_;  // the folder's canonical path
};

// The lock of a stage's output folder: taken at once when the folder exists, so that a second
// command into it is refused before it does its work, else where the stage creates the folder.
class OutputFolderLock {
 public:
  explicit OutputFolderLock(std::filesystem::path output);
  // Creates the folder (CreateFolder, util/new_folder.h) and locks it, if not locked yet.
  void CreateAndLock();

 private:
  std::filesystem::path output_;
  std::optional<FolderLock> lock_;
};

// The folder a workspace database lies in ("." for a bare file name).
std::filesystem::path WorkspaceFolder(const std::filesystem::path& workspace);

}  // namespace varsfm
