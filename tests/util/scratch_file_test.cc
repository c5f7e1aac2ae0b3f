#include "varsfm/util/scratch_file.h"

#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "support/test_data.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;

TEST(ScratchFile, ReadsBackEveryByteAndLeavesNoFile) {
  testing::TempDir tmp("scratch_file");
  std::string expected;
  {
    ScratchFile file(tmp.path());
    // Appends that straddle the 1 MB buffer, one larger than it, and small ones.
    for (int i = 0; i < 3000; ++i) {
      const std::string piece(static_cast<size_t>(i % 997 + 1), static_cast<char>('a' + i % 26));
      file.Append(piece.data(), piece.size());
      expected += piece;
    }
    const std::string large(3u << 20, 'z');
    file.Append(large.data(), large.size());
    expected += large;
    EXPECT_EQ(file.size(), expected.size());
    EXPECT_EQ(fs::directory_iterator(tmp.path()), fs::directory_iterator());
    std::ostringstream out;
    file.CopyTo(out);
    EXPECT_EQ(out.str(), expected);
    // Appending after a copy goes on where it stopped.
    file.Append("tail", 4);
    std::ostringstream again;
    file.CopyTo(again);
    EXPECT_EQ(again.str(), expected + "tail");
  }
  EXPECT_EQ(fs::directory_iterator(tmp.path()), fs::directory_iterator());
}

TEST(ScratchFile, MissingFolderIsOneError) {
  testing::TempDir tmp("scratch_file_missing");
  EXPECT_THROW(ScratchFile(tmp.path() / "absent"), Error);
}

}  // namespace
}  // namespace varsfm
