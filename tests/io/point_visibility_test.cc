#include "varsfm/io/point_visibility.h"

#include <gtest/gtest.h>

#include <fstream>

#include "support/test_data.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

TEST(PointVisibility, RoundTripIsExact) {
  const PointVisibility visibility = {{1, 2, 5}, {}, {7}, {3, 4, 4000000000u}};
  testing::TempDir tmp("point_visibility");
  WritePointVisibility(tmp.path() / "dense.ply.vis", visibility);
  EXPECT_EQ(ReadPointVisibility(tmp.path() / "dense.ply.vis"), visibility);
  // COLMAP's layout: 8-byte count, then per point a 4-byte count and 4-byte ids.
  EXPECT_EQ(std::filesystem::file_size(tmp.path() / "dense.ply.vis"), 8u + 4 * 4 + 4 * 7);
}

TEST(PointVisibility, DamagedFilesAreOneError) {
  testing::TempDir tmp("point_visibility_damaged");
  const auto file = tmp.path() / "v.vis";
  EXPECT_THROW(ReadPointVisibility(file), Error);  // missing
  WritePointVisibility(file, {{1, 2}, {3}});
  std::filesystem::resize_file(file, std::filesystem::file_size(file) - 2);
  EXPECT_THROW(ReadPointVisibility(file), Error);  // truncated
  {
    std::ofstream out(file, std::ios::binary);
    const uint64_t huge = 1ull << 60;  // a count no file of this size can hold
    out.write(reinterpret_cast<const char*>(&huge), sizeof(huge));
  }
  EXPECT_THROW(ReadPointVisibility(file), Error);
}

}  // namespace
}  // namespace varsfm
