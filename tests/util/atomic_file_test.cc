#include "varsfm/util/atomic_file.h"

#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "support/test_data.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;

std::string ReadText(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

size_t NumEntries(const fs::path& dir) {
  return static_cast<size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

TEST(WriteFileAtomically, ReplacesTheFileAndLeavesNoTemporary) {
  testing::TempDir tmp("atomic_file_replace");
  const fs::path file = tmp.path() / "a.txt";
  std::ofstream(file) << "old";
  WriteFileAtomically(file, [](std::ostream& out) { out << "new\n" << 42; });
  EXPECT_EQ(ReadText(file), "new\n42");
  EXPECT_EQ(NumEntries(tmp.path()), 1u);
}

TEST(WriteFileAtomically, AFailingWriterKeepsTheOldFileAndRethrows) {
  testing::TempDir tmp("atomic_file_failure");
  const fs::path file = tmp.path() / "a.txt";
  std::ofstream(file) << "old";
  EXPECT_THROW(WriteFileAtomically(file,
                                   [](std::ostream& out) {
                                     out << "half";
                                     throw std::runtime_error("stop");
                                   }),
               std::runtime_error);
  EXPECT_EQ(ReadText(file), "old");
  EXPECT_EQ(NumEntries(tmp.path()), 1u);
}

TEST(WriteFileAtomically, AMissingFolderIsOneErrorNamingTheFile) {
  testing::TempDir tmp("atomic_file_no_folder");
  const fs::path file = tmp.path() / "missing" / "a.txt";
  try {
    WriteFileAtomically(file, [](std::ostream& out) { out << "x"; });
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
}

TEST(WriteFileViaTemporary, AWriterThatCreatesNothingIsAnError) {
  testing::TempDir tmp("atomic_file_via");
  const fs::path file = tmp.path() / "a.bin";
  WriteFileViaTemporary(file, [&](const fs::path& temporary) {
    EXPECT_EQ(temporary.parent_path(), file.parent_path());
    std::ofstream(temporary) << "via";
  });
  EXPECT_EQ(ReadText(file), "via");
  EXPECT_THROW(WriteFileViaTemporary(tmp.path() / "b.bin", [](const fs::path&) {}), Error);
  EXPECT_EQ(NumEntries(tmp.path()), 1u);
}

TEST(WriteFilesAtomically, AFolderAppearsWithAllItsFilesOrNotAtAll) {
  testing::TempDir tmp("atomic_file_folder");
  const fs::path dir = tmp.path() / "model";
  EXPECT_THROW(WriteFilesAtomically(dir, {"a", "b"},
                                    [](const fs::path& t) { std::ofstream(t / "a") << "1"; }),
               Error);
  EXPECT_FALSE(fs::exists(dir));
  EXPECT_EQ(NumEntries(tmp.path()), 0u);
  WriteFilesAtomically(dir, {"a", "b"}, [](const fs::path& t) {
    std::ofstream(t / "a") << "1";
    std::ofstream(t / "b") << "2";
  });
  EXPECT_EQ(ReadText(dir / "a"), "1");
  EXPECT_EQ(ReadText(dir / "b"), "2");
}

}  // namespace
}  // namespace varsfm
