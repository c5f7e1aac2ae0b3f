#pragma once
// One varsfm command at a time writes a folder or a workspace. Two commands writing one output
// folder at once (a second terminal, a script started twice) interleave their results: one
// removes the outputs the other has just written (RemoveOutputsAfter), both rewrite
// summary.json, and the last to finish wins file by file; a `match` into a workspace that `map`
// is reading changes the matches under it. A command holds this lock for as long as it runs:
// exclusive on what it writes (an output folder, a workspace it extracts or matches into),
// shared on a workspace it only reads (`map`: several maps of one workspace may run at once). A
// command that conflicts is refused at once with a one-line error.
//
// The lock is flock(2) on the folder or the workspace file itself, so nothing is written beside
// them and no stale lock outlives a crashed or killed process (the kernel releases it with the
// process). flock and SQLite's own fcntl locks do not interact on Linux. Within one process the
// lock is re-entrant: `run` holds its output folder and calls the stages, each of which locks it
// (and the workspace in it) again.
#include <filesystem>
#include <optional>
#include <string>

namespace varsfm {

enum class LockMode { kExclusive, kShared };

class PathLock {
 public:
  // Locks `path`, an existing folder or file. Throws varsfm::Error when another process holds a
  // conflicting lock ("... is in use by another varsfm command ...") or `path` does not exist;
  // where the file system cannot lock (or `path` cannot be opened), warns and goes on unlocked.
  explicit PathLock(const std::filesystem::path& path, LockMode mode = LockMode::kExclusive);
  ~PathLock();
  PathLock(const PathLock&) = delete;
  PathLock& operator=(const PathLock&) = delete;

 private:
  std::string key_;  // the canonical path
};

// The exclusive lock of a stage's output folder: taken at once when the folder exists, so that a
// second command into it is refused before it does its work, else where the stage creates it.
class OutputFolderLock {
 public:
  explicit OutputFolderLock(std::filesystem::path output);
  // Creates the folder (CreateFolder, util/new_folder.h) and locks it, if not locked yet.
  void CreateAndLock();

 private:
  std::filesystem::path output_;
  std::optional<PathLock> lock_;
};

}  // namespace varsfm
