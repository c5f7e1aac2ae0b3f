// The workspace is COLMAP 3.8's database: same schema text, and COLMAP's own tools read what
// varsfm writes and varsfm reads what they write.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <map>
#include <random>
#include <regex>

#include "support/test_data.h"
#include "varsfm/io/database.h"
#include "varsfm/io/result_settings.h"

namespace varsfm {
namespace {

using testing::RunCommand;
using testing::TempDir;

// name -> sql of every table and index in sqlite_master (SQLite's own tables left out).
std::map<std::string, std::string> Schema(const std::filesystem::path& path) {
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  sqlite3_stmt* stmt = nullptr;
  sqlite3_prepare_v2(db,
                     "SELECT name, sql FROM sqlite_master WHERE sql IS NOT NULL AND name NOT "
                     "LIKE 'sqlite_%'",
                     -1, &stmt, nullptr);
  std::map<std::string, std::string> schema;
  while (sqlite3_step(stmt) == SQLITE_ROW) {
    schema[reinterpret_cast<const char*>(sqlite3_column_text(stmt, 0))] =
        reinterpret_cast<const char*>(sqlite3_column_text(stmt, 1));
  }
  sqlite3_finalize(stmt);
  sqlite3_close(db);
  return schema;
}

// One space between tokens, none inside parentheses or before commas; "IF NOT EXISTS" dropped
// (SQLite does not keep it in sqlite_master).
std::string Normalize(std::string sql) {
  sql = std::regex_replace(sql, std::regex(" IF NOT EXISTS"), "");
  sql = std::regex_replace(sql, std::regex("\\s+"), " ");
  sql = std::regex_replace(sql, std::regex(" ?([(),]) ?"), "$1");
  return sql;
}

// COLMAP 3.8's schema, as `colmap database_creator` writes it.
const std::map<std::string, std::string> kColmap38 = {
    {"cameras",
     "CREATE TABLE IF NOT EXISTS cameras (camera_id INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, "
     "model INTEGER NOT NULL, width INTEGER NOT NULL, height INTEGER NOT NULL, params BLOB, "
     "prior_focal_length INTEGER NOT NULL)"},
    {"images",
     "CREATE TABLE IF NOT EXISTS images (image_id INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, "
     "name TEXT NOT NULL UNIQUE, camera_id INTEGER NOT NULL, prior_qw REAL, prior_qx REAL, "
     "prior_qy REAL, prior_qz REAL, prior_tx REAL, prior_ty REAL, prior_tz REAL, CONSTRAINT "
     "image_id_check CHECK(image_id >= 0 and image_id < 2147483647), FOREIGN KEY(camera_id) "
     "REFERENCES cameras(camera_id))"},
    {"index_name", "CREATE UNIQUE INDEX IF NOT EXISTS index_name ON images(name)"},
    {"keypoints",
     "CREATE TABLE IF NOT EXISTS keypoints (image_id INTEGER PRIMARY KEY NOT NULL, rows INTEGER "
     "NOT NULL, cols INTEGER NOT NULL, data BLOB, FOREIGN KEY(image_id) REFERENCES "
     "images(image_id) ON DELETE CASCADE)"},
    {"descriptors",
     "CREATE TABLE IF NOT EXISTS descriptors (image_id INTEGER PRIMARY KEY NOT NULL, rows "
     "INTEGER NOT NULL, cols INTEGER NOT NULL, data BLOB, FOREIGN KEY(image_id) REFERENCES "
     "images(image_id) ON DELETE CASCADE)"},
    {"matches",
     "CREATE TABLE IF NOT EXISTS matches (pair_id INTEGER PRIMARY KEY NOT NULL, rows INTEGER NOT "
     "NULL, cols INTEGER NOT NULL, data BLOB)"},
    {"two_view_geometries",
     "CREATE TABLE IF NOT EXISTS two_view_geometries (pair_id INTEGER PRIMARY KEY NOT NULL, rows "
     "INTEGER NOT NULL, cols INTEGER NOT NULL, data BLOB, config INTEGER NOT NULL, F BLOB, E "
     "BLOB, H BLOB, qvec BLOB, tvec BLOB)"},
};

bool HaveColmap() { return RunCommand("command -v colmap") == 0; }

TEST(ColmapSchema, SameTablesAsColmap38) {
  TempDir dir("schema");
  const auto path = dir.path() / "database.db";
  { Database db(path); }
  const auto schema = Schema(path);
  ASSERT_EQ(schema.size(), kColmap38.size());
  for (const auto& [name, sql] : kColmap38) {
    ASSERT_TRUE(schema.count(name)) << name;
    EXPECT_EQ(Normalize(schema.at(name)), Normalize(sql)) << name;
  }
}

TEST(ColmapSchema, ByteIdenticalToColmapDatabaseCreator) {
  if (!HaveColmap()) GTEST_SKIP() << "colmap is not installed; skipping";
  TempDir dir("schema");
  std::string output;
  ASSERT_EQ(
      RunCommand("colmap database_creator --database_path " + (dir.path() / "colmap.db").string(),
                 &output),
      0)
      << output;
  { Database db(dir.path() / "varsfm.db"); }
  EXPECT_EQ(Schema(dir.path() / "varsfm.db"), Schema(dir.path() / "colmap.db"));
}

TEST(ColmapSchema, OpensAndWritesADatabaseMadeByColmap) {
  if (!HaveColmap()) GTEST_SKIP() << "colmap is not installed; skipping";
  TempDir dir("schema");
  const auto path = dir.path() / "colmap.db";
  std::string output;
  ASSERT_EQ(RunCommand("colmap database_creator --database_path " + path.string(), &output), 0)
      << output;
  {
    Database db(path);
    EXPECT_EQ(db.NumImages(), 0u);
    const camera_t camera = db.WriteCamera({0, 0, 100, 80, {90, 50, 40}, false});
    db.WriteImage({0, "a.jpg", camera});
  }
  Database db(path);
  EXPECT_EQ(db.ReadAllImages().at(0).name, "a.jpg");
  EXPECT_EQ(db.ReadCamera(1)->params, (std::vector<double>{90, 50, 40}));
}

// varsfm writes cameras, images and features (and its record of their settings, in tables of its
// own); COLMAP's matcher reads them and writes matches and verified geometry; varsfm reads those
// back. A synthetic 3D scene seen by two known cameras, so
// the geometry COLMAP estimates can be checked against the keypoints.
TEST(ColmapSchema, ColmapMatcherRoundTrip) {
  if (!HaveColmap()) GTEST_SKIP() << "colmap is not installed; skipping";
  TempDir dir("schema");
  const auto path = dir.path() / "database.db";
  constexpr int kPoints = 300;
  constexpr double kFocal = 500, kCx = 320, kCy = 240;
  const Eigen::Matrix3d K =
      (Eigen::Matrix3d() << kFocal, 0, kCx, 0, kFocal, kCy, 0, 0, 1).finished();
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.15, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Vector3d t(-0.6, 0.05, 0.1);

  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-1, 1);
  FeatureKeypoints k1, k2;
  FeatureDescriptors descriptors(kPoints, 128);
  for (int i = 0; i < kPoints; ++i) {
    const Eigen::Vector3d X(uniform(rng), 0.75 * uniform(rng), 5 + uniform(rng));
    const Eigen::Vector3d x1 = K * X, x2 = K * (R * X + t);
    k1.emplace_back(x1.x() / x1.z(), x1.y() / x1.z(), 2.0f, 0.0f);
    k2.emplace_back(x2.x() / x2.z(), x2.y() / x2.z(), 2.0f, 0.0f);
    // SIFT-like descriptors (non-negative, L2 norm 512) that only the same point matches.
    Eigen::VectorXd d(128);
    for (int c = 0; c < 128; ++c) d[c] = 0.5 * (1 + uniform(rng));
    d *= 512 / d.norm();
    for (int c = 0; c < 128; ++c) descriptors(i, c) = static_cast<uint8_t>(std::lround(d[c]));
  }
  {
    Database db(path);
    Database::Transaction transaction(db);
    for (const auto& [name, keypoints] : {std::pair{"1.jpg", &k1}, std::pair{"2.jpg", &k2}}) {
      const camera_t camera = db.WriteCamera({0, 0, 640, 480, {kFocal, kCx, kCy}, true});
      const image_t image = db.WriteImage({0, name, camera});
      db.WriteKeypoints(image, *keypoints);
      db.WriteDescriptors(image, descriptors);
      ResultSettings record(db);
      record.WriteImageSettings(image, record.Id("extract", "synthetic"));
    }
    transaction.Commit();
  }
  std::string output;
  ASSERT_EQ(RunCommand("colmap exhaustive_matcher --SiftMatching.use_gpu 0 --database_path " +
                           path.string(),
                       &output),
            0)
      << output;

  Database db(path);
  EXPECT_EQ(db.NumMatchedPairs(), 1u);
  EXPECT_EQ(db.NumVerifiedPairs(), 1u);
  const FeatureMatches matches = db.ReadMatches(2, 1);
  EXPECT_GT(matches.size(), kPoints * 9 / 10);
  for (const FeatureMatch& m : matches) EXPECT_EQ(m.point2D_idx1, m.point2D_idx2);

  const auto epipolar_distance = [](const Eigen::Matrix3d& F, const FeatureKeypoint& a,
                                    const FeatureKeypoint& b) {
    const Eigen::Vector3d line = F * Eigen::Vector3d(a.x, a.y, 1);
    return std::abs(line.dot(Eigen::Vector3d(b.x, b.y, 1))) / line.head<2>().norm();
  };
  const TwoViewGeometry g12 = db.ReadTwoViewGeometry(1, 2);
  const TwoViewGeometry g21 = db.ReadTwoViewGeometry(2, 1);
  EXPECT_EQ(g12.config, TwoViewGeometry::kCalibrated);
  EXPECT_GT(g12.inlier_matches.size(), kPoints * 9 / 10);
  EXPECT_EQ(g21.inlier_matches.size(), g12.inlier_matches.size());
  const Eigen::Matrix3d E_in_pixels = K.inverse().transpose() * g12.E * K.inverse();
  for (size_t i = 0; i < g12.inlier_matches.size(); ++i) {
    const FeatureMatch m = g12.inlier_matches[i];
    // x2^T F x1 = 0 for the order asked for, x1^T F' x2 = 0 for the swapped one.
    EXPECT_LT(epipolar_distance(g12.F, k1[m.point2D_idx1], k2[m.point2D_idx2]), 0.5);
    EXPECT_LT(epipolar_distance(E_in_pixels, k1[m.point2D_idx1], k2[m.point2D_idx2]), 0.5);
    const FeatureMatch s = g21.inlier_matches[i];
    EXPECT_LT(epipolar_distance(g21.F, k2[s.point2D_idx1], k1[s.point2D_idx2]), 0.5);
  }
}

}  // namespace
}  // namespace varsfm
