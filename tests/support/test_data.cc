#include "support/test_data.h"

#include <array>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>

namespace varsfm::testing {

std::filesystem::path SharedDataDir() {
  const auto dir = std::filesystem::path(VARSFM_SOURCE_DIR) / ".." / "shared" / "data";
  if (!std::filesystem::is_directory(dir)) return {};
  return std::filesystem::weakly_canonical(dir);
}

std::filesystem::path SourceDir() { return VARSFM_SOURCE_DIR; }

bool ValidateGltf(const std::filesystem::path& file, int* exit_code, std::string* output,
                  std::string* why) {
  if (RunCommand("command -v node >/dev/null 2>&1") != 0) {
    *why = "node is not installed";
    return false;
  }
  const auto validator = SourceDir() / "scripts" / "node" / "node_modules" / "gltf-validator";
  if (!std::filesystem::is_directory(validator)) {
    *why = "gltf-validator is not installed (scripts/install_deps.sh --with-colmap)";
    return false;
  }
  *exit_code = RunCommand(
      "node " + ShellQuote(SourceDir() / "scripts" / "validate_gltf.js") + " " + ShellQuote(file),
      output);
  return true;
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

std::filesystem::path CopyFileHead(const std::filesystem::path& from,
                                   const std::filesystem::path& to, double fraction) {
  std::ifstream in(from, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::ofstream(to, std::ios::binary)
      << bytes.substr(0, static_cast<size_t>(fraction * static_cast<double>(bytes.size())));
  return to;
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

nlohmann::json EvaluateCommand(const std::filesystem::path& model, const std::filesystem::path& gt,
                               const std::filesystem::path& json_file) {
  std::string output;
  const int code = RunCommand(ShellQuote(VarsfmBinary()) + " evaluate " + ShellQuote(model) +
                                  " --gt " + ShellQuote(gt) + " --json " + ShellQuote(json_file),
                              &output);
  EXPECT_EQ(code, 0) << output;
  if (code != 0) return nlohmann::json::object();
  std::ifstream in(json_file);
  return nlohmann::json::parse(in);
}

}  // namespace varsfm::testing
