#pragma once
// Test helpers: where the shared real-photograph data lives, the varsfm binary, temp folders.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace varsfm::testing {

// ../shared/data seen from the project root, or an empty path when it is absent.
std::filesystem::path SharedDataDir();

// The project's source tree (for its scripts/).
std::filesystem::path SourceDir();

// Runs scripts/validate_gltf.js (the Khronos glTF-Validator) on `file`. Returns false and sets
// `why` when node or the validator is not installed (the caller skips); otherwise returns true
// with the validator's exit code (0: no errors) and output.
bool ValidateGltf(const std::filesystem::path& file, int* exit_code, std::string* output,
                  std::string* why);

// The command-line tool built beside the tests (build/varsfm).
std::filesystem::path VarsfmBinary();

// A fresh, empty folder under the build tree, removed when the object dies.
class TempDir {
 public:
  explicit TempDir(const std::string& name);
  ~TempDir();
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// `path` quoted for a POSIX shell (single quotes; embedded ones escaped).
std::string ShellQuote(const std::filesystem::path& path);

// Writes the first `fraction` (0..1) of the file `from`'s bytes to `to` (a copy interrupted, a
// download stopped) and returns `to`.
std::filesystem::path CopyFileHead(const std::filesystem::path& from,
                                   const std::filesystem::path& to, double fraction);

// Runs a shell command, returning its exit code; stdout+stderr go to `output` if given.
int RunCommand(const std::string& command, std::string* output = nullptr);

// `varsfm evaluate MODEL --gt GT --json JSON_FILE`, parsed. A failed command fails the calling
// test (with its output) and gives an empty object.
nlohmann::json EvaluateCommand(const std::filesystem::path& model, const std::filesystem::path& gt,
                               const std::filesystem::path& json_file);

}  // namespace varsfm::testing

// Skips the current test (with a message) unless ../shared/data/<relative> exists; otherwise
// defines `data_path` as the full path.
#define VARSFM_REQUIRE_SHARED_DATA(data_path, relative)                                    \
  const std::filesystem::path data_path = ::varsfm::testing::SharedDataDir() / (relative); \
  if (::varsfm::testing::SharedDataDir().empty() || !std::filesystem::exists(data_path))   \
  GTEST_SKIP() << "../shared/data/" << (relative) << " is absent; skipping"
