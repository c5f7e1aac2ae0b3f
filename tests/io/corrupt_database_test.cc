// Workspace rows that crashed the reader (the overflow found by fuzz/database_blob_fuzzer.cc's
// smoke run, the others by review): sizes (rows, cols) that are negative, or whose product or
// byte count overflows to match a small blob. Each must be one varsfm::Error, before anything is
// allocated from the size.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <string>

#include "support/test_data.h"
#include "varsfm/io/database.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

using testing::TempDir;

// A workspace with images 1 and 2, then `sql` run on it through a plain SQLite connection
// (foreign keys off), as a foreign tool or a damaged disk might leave it.
void MakeWorkspace(const std::filesystem::path& path, const std::string& sql) {
  {
    Database db(path);
    const camera_t camera = db.WriteCamera({0, 0, 64, 48, {50, 32, 24}, false});
    db.WriteImage({0, "a.jpg", camera});
    db.WriteImage({0, "b.jpg", camera});
  }
  sqlite3* raw = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &raw), SQLITE_OK);
  EXPECT_EQ(sqlite3_exec(raw, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK) << sql;
  sqlite3_close(raw);
}

const std::string kPair = std::to_string(Database::ImagePairToPairId(1, 2));

TEST(CorruptDatabase, NegativeKeypointRowsAndColumns) {
  TempDir dir("corrupt_db");
  const auto path = dir.path() / "database.db";
  // -1 x -1 = 1 value, and the blob holds one float: the row count was taken as 2^64 - 1.
  MakeWorkspace(path, "INSERT INTO keypoints VALUES(1, -1, -1, x'0000803f')");
  EXPECT_THROW(Database(path).ReadKeypoints(1), Error);
}

TEST(CorruptDatabase, KeypointSizeOverflowingToAnEmptyBlob) {
  TempDir dir("corrupt_db");
  const auto path = dir.path() / "database.db";
  // 2^61 x 2 floats is 2^64 bytes, 0 once wrapped: an empty blob matched it.
  MakeWorkspace(path, "INSERT INTO keypoints VALUES(1, 2305843009213693952, 2, x'')");
  EXPECT_THROW(Database(path).ReadKeypoints(1), Error);
  // 2^62 x 4 overflows int64 itself.
  const auto path2 = dir.path() / "database2.db";
  MakeWorkspace(path2, "INSERT INTO keypoints VALUES(1, 4611686018427387904, 4, x'')");
  EXPECT_THROW(Database(path2).ReadKeypoints(1), Error);
}

TEST(CorruptDatabase, KeypointRowsWithoutColumns) {
  TempDir dir("corrupt_db");
  const auto path = dir.path() / "database.db";
  // 10^12 rows of 0 columns fit an empty blob; the column count is checked before sizing.
  MakeWorkspace(path, "INSERT INTO keypoints VALUES(1, 1000000000000, 0, x'')");
  EXPECT_THROW(Database(path).ReadKeypoints(1), Error);
}

TEST(CorruptDatabase, NegativeDescriptorSize) {
  TempDir dir("corrupt_db");
  const auto path = dir.path() / "database.db";
  MakeWorkspace(path, "INSERT INTO descriptors VALUES(1, -2, -3, x'010203040506')");
  EXPECT_THROW(Database(path).ReadDescriptors(1), Error);
}

TEST(CorruptDatabase, MatchCountOverflow) {
  TempDir dir("corrupt_db");
  const auto path = dir.path() / "database.db";
  MakeWorkspace(path, "INSERT INTO matches VALUES(" + kPair + ", 4611686018427387904, 2, x'');" +
                          "INSERT INTO two_view_geometries VALUES(" + kPair +
                          ", 2305843009213693952, 2, x'', 2, NULL, NULL, NULL, NULL, NULL)");
  const Database db(path);
  EXPECT_THROW(db.ReadMatches(1, 2), Error);
  EXPECT_THROW(db.ReadTwoViewGeometry(2, 1), Error);
  EXPECT_THROW(db.ReadAllTwoViewGeometries(), Error);
}

TEST(CorruptDatabase, ValidRowsStillRead) {
  TempDir dir("corrupt_db");
  const auto path = dir.path() / "database.db";
  MakeWorkspace(path,
                "INSERT INTO keypoints VALUES(1, 1, 2, x'0000803f00000040');"
                "INSERT INTO keypoints VALUES(2, 0, 0, x'');"
                "INSERT INTO descriptors VALUES(1, 1, 3, x'010203')");
  const Database db(path);
  const FeatureKeypoints keypoints = db.ReadKeypoints(1);
  ASSERT_EQ(keypoints.size(), 1u);
  EXPECT_EQ(keypoints[0].x, 1.0f);
  EXPECT_EQ(keypoints[0].y, 2.0f);
  EXPECT_TRUE(db.ReadKeypoints(2).empty());
  EXPECT_EQ(db.ReadDescriptors(1).cols(), 3);
}

}  // namespace
}  // namespace varsfm
