#include "varsfm/util/new_folder.h"

#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "support/test_data.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;

TEST(CreateFolder, CreatesParentsAndAcceptsAnExistingFolder) {
  testing::TempDir tmp("create_folder");
  const fs::path dir = tmp.path() / "a" / "b";
  CreateFolder(dir);
  EXPECT_TRUE(fs::is_directory(dir));
  CreateFolder(dir);  // already there: nothing to do
  EXPECT_TRUE(fs::is_directory(dir));
}

// Under a file, or where a file of that name stands, the error is one line naming the folder.
TEST(CreateFolder, ImpossibleFolderIsAnErrorNamingIt) {
  testing::TempDir tmp("create_folder_error");
  const fs::path file = tmp.path() / "file";
  std::ofstream(file) << "x";
  for (const fs::path& dir : {file / "sub", file}) {
    try {
      CreateFolder(dir);
      ADD_FAILURE() << dir << " was accepted";
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(dir.string()), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  }
}

}  // namespace
}  // namespace varsfm
