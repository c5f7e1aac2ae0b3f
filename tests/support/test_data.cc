#include "support/test_data.h"

#include <array>
#include <cstdio>
#include <memory>

namespace varsfm::testing {

std::filesystem::path SharedDataDir() {
  const auto dir = std::filesystem::path(VARSFM_SOURCE_DIR) / ".." / "shared" / "data";
  if (!std::filesystem::is_directory(dir)) return {};
  return std::filesystem::weakly_canonical(dir);
}

std::filesystem::path VarsfmBinary() { return std::filesystem::path(VARSFM_BINARY_DIR) / "varsfm"; }

TempDir::TempDir(const std::string& name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string unique = name;
  if (info != nullptr) unique += std::string("_") + info->test_suite_name() + "_" + info->name();
  path_ = std::filesystem::path(VARSFM_BINARY_DIR) / "test_tmp" / unique;
  std::filesystem::remove_all(path_);
  std::filesystem::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

std::string ShellQuote(const std::filesystem::path& path) {
  std::string quoted = "'";
  for (const char c : path.string()) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

int RunCommand(const std::string& command, std::string* output) {
  const std::string full = command + " 2>&1";
  FILE* pipe = popen(full.c_str(), "r");
  if (pipe == nullptr) return -1;
  std::array<char, 4096> buffer;
  std::string text;
  size_t n;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) text.append(buffer.data(), n);
  const int status = pclose(pipe);
  if (output != nullptr) *output = text;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace varsfm::testing
