#include "varsfm/io/database.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "support/test_data.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

using testing::TempDir;

// Direct SQL on a database file: checks what is stored, independently of Database's reader.
class RawDb {
 public:
  explicit RawDb(const std::filesystem::path& path) {
    if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READWRITE, nullptr) != SQLITE_OK) {
      throw std::runtime_error("cannot open " + path.string());
    }
  }
  ~RawDb() { sqlite3_close_v2(db_); }

  // The first row's columns, blobs as raw bytes, NULL as "<null>".
  std::vector<std::string> Row(const std::string& sql) const {
    sqlite3_stmt* stmt = nullptr;
    EXPECT_EQ(sqlite3_prepare_v2(db_, sql.c_str(), -1, &stmt, nullptr), SQLITE_OK) << sql;
    std::vector<std::string> row;
    if (sqlite3_step(stmt) == SQLITE_ROW) {
      for (int i = 0; i < sqlite3_column_count(stmt); ++i) {
        if (sqlite3_column_type(stmt, i) == SQLITE_NULL) {
          row.emplace_back("<null>");
          continue;
        }
        const auto* data = static_cast<const char*>(sqlite3_column_blob(stmt, i));
        row.emplace_back(data, sqlite3_column_bytes(stmt, i));
      }
    }
    sqlite3_finalize(stmt);
    return row;
  }
  void Exec(const std::string& sql) const {
    ASSERT_EQ(sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK) << sql;
  }
  sqlite3* get() const { return db_; }

 private:
  sqlite3* db_ = nullptr;
};

template <typename T>
std::vector<T> BlobAs(const std::string& bytes) {
  std::vector<T> values(bytes.size() / sizeof(T));
  std::memcpy(values.data(), bytes.data(), values.size() * sizeof(T));
  return values;
}

DbCamera MakeCamera(double focal) {
  DbCamera camera;
  camera.model_id = 2;  // SIMPLE_RADIAL
  camera.width = 640;
  camera.height = 480;
  camera.params = {focal, 320, 240, -0.01};
  camera.has_prior_focal_length = true;
  return camera;
}

// Creates a camera and `n` images named img<i>.jpg; returns the image ids.
std::vector<image_t> AddImages(Database& db, int n) {
  const camera_t camera_id = db.WriteCamera(MakeCamera(500));
  std::vector<image_t> ids;
  for (int i = 0; i < n; ++i)
    ids.push_back(db.WriteImage({0, "img" + std::to_string(i) + ".jpg", camera_id}));
  return ids;
}

TwoViewGeometry MakeGeometry() {
  TwoViewGeometry tvg;
  tvg.config = TwoViewGeometry::kCalibrated;
  tvg.F << 1e-6, -2e-5, 3e-3, 4e-5, 5e-7, -6e-3, -7e-3, 8e-3, 1;
  tvg.E << 0.1, -0.2, 0.3, 0.4, 0.05, -0.6, -0.7, 0.8, 0.09;
  tvg.H << 1.1, 0.02, 5, -0.03, 0.95, -7, 1e-4, 2e-4, 1;
  tvg.cam2_from_cam1_rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
  tvg.cam2_from_cam1_translation = Eigen::Vector3d(0.5, -0.25, 0.1);
  tvg.inlier_matches = {{0, 5}, {1, 7}, {4, 2}};
  return tvg;
}

FeatureMatches Swapped(FeatureMatches matches) {
  for (auto& m : matches) std::swap(m.point2D_idx1, m.point2D_idx2);
  return matches;
}

TEST(DatabasePairId, EncodesAsColmap) {
  EXPECT_EQ(Database::ImagePairToPairId(1, 2), 2147483647ull + 2);
  EXPECT_EQ(Database::ImagePairToPairId(2, 1), Database::ImagePairToPairId(1, 2));
  EXPECT_EQ(Database::ImagePairToPairId(3, 7), 3 * 2147483647ull + 7);
  EXPECT_TRUE(Database::SwapImagePair(7, 3));
  EXPECT_FALSE(Database::SwapImagePair(3, 7));
  for (auto [a, b] : std::vector<std::pair<image_t, image_t>>{
           {1, 2}, {5, 3}, {1, 2147483646}, {2147483645, 2147483646}}) {
    const auto [id1, id2] = Database::PairIdToImagePair(Database::ImagePairToPairId(a, b));
    EXPECT_EQ(id1, std::min(a, b));
    EXPECT_EQ(id2, std::max(a, b));
  }
}

TEST(Database, CamerasRoundTrip) {
  TempDir dir("db");
  Database db(dir.path() / "database.db");
  DbCamera a = MakeCamera(500);
  DbCamera b = MakeCamera(700);
  b.model_id = 0;
  b.params = {700, 100, 50};
  b.has_prior_focal_length = false;
  a.camera_id = db.WriteCamera(a);
  b.camera_id = db.WriteCamera(b);
  EXPECT_EQ(a.camera_id, 1u);  // ids start at 1, as COLMAP's
  EXPECT_EQ(b.camera_id, 2u);
  EXPECT_EQ(db.NumCameras(), 2u);

  const auto read = db.ReadCamera(b.camera_id);
  ASSERT_TRUE(read);
  EXPECT_EQ(read->model_id, 0);
  EXPECT_EQ(read->width, 640);
  EXPECT_EQ(read->height, 480);
  EXPECT_EQ(read->params, b.params);
  EXPECT_FALSE(read->has_prior_focal_length);
  EXPECT_FALSE(db.ReadCamera(99));

  a.params[0] = 555;
  a.width = 1000;
  db.UpdateCamera(a);
  const auto all = db.ReadAllCameras();
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].camera_id, a.camera_id);
  EXPECT_EQ(all[0].params, a.params);
  EXPECT_EQ(all[0].width, 1000);
  EXPECT_TRUE(all[0].has_prior_focal_length);

  DbCamera missing = a;
  missing.camera_id = 42;
  EXPECT_THROW(db.UpdateCamera(missing), Error);
}

TEST(Database, ImagesRoundTrip) {
  TempDir dir("db");
  Database db(dir.path() / "database.db");
  const camera_t c1 = db.WriteCamera(MakeCamera(500));
  const camera_t c2 = db.WriteCamera(MakeCamera(600));
  const image_t i1 = db.WriteImage({0, "a/b.jpg", c1});
  const image_t i2 = db.WriteImage({0, "c.png", c2});
  EXPECT_EQ(i1, 1u);
  EXPECT_EQ(i2, 2u);
  EXPECT_EQ(db.NumImages(), 2u);

  const auto by_id = db.ReadImage(i2);
  ASSERT_TRUE(by_id);
  EXPECT_EQ(by_id->name, "c.png");
  EXPECT_EQ(by_id->camera_id, c2);
  const auto by_name = db.ReadImageWithName("a/b.jpg");
  ASSERT_TRUE(by_name);
  EXPECT_EQ(by_name->image_id, i1);
  EXPECT_EQ(by_name->camera_id, c1);
  EXPECT_FALSE(db.ReadImage(7));
  EXPECT_FALSE(db.ReadImageWithName("nope.jpg"));
  const auto all = db.ReadAllImages();
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].image_id, i1);
  EXPECT_EQ(all[1].name, "c.png");

  EXPECT_THROW(db.WriteImage({0, "c.png", c1}), Error);  // names are unique
  EXPECT_THROW(db.WriteImage({0, "d.png", 99}), Error);  // foreign keys are on
  EXPECT_EQ(db.NumImages(), 2u);
}

TEST(Database, FeaturesRoundTrip) {
  TempDir dir("db");
  const auto path = dir.path() / "database.db";
  image_t id;
  FeatureKeypoints keypoints;
  FeatureDescriptors descriptors(3, 128);
  {
    Database db(path);
    id = AddImages(db, 1)[0];
    keypoints = {FeatureKeypoint(1.5f, 2.5f, 3.0f, 0.7f), FeatureKeypoint(10, 20),
                 FeatureKeypoint(100.25f, 0.5f, 1.0f, -2.0f)};
    keypoints[1].a12 = 0.25f;  // a general affine shape survives too
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 128; ++c) descriptors(r, c) = static_cast<uint8_t>(r * 50 + c);
    EXPECT_FALSE(db.ExistsKeypoints(id));
    EXPECT_FALSE(db.ExistsDescriptors(id));
    EXPECT_TRUE(db.ReadKeypoints(id).empty());
    db.WriteKeypoints(id, keypoints);
    db.WriteDescriptors(id, descriptors);
    EXPECT_THROW(db.WriteKeypoints(99, keypoints), Error);  // no such image
  }
  Database db(path);  // reopened: what is read comes from the file
  EXPECT_TRUE(db.ExistsKeypoints(id));
  EXPECT_TRUE(db.ExistsDescriptors(id));
  const FeatureKeypoints read = db.ReadKeypoints(id);
  ASSERT_EQ(read.size(), keypoints.size());
  for (size_t i = 0; i < read.size(); ++i) {
    EXPECT_EQ(std::memcmp(&read[i], &keypoints[i], sizeof(FeatureKeypoint)), 0) << i;
  }
  EXPECT_EQ(db.ReadDescriptors(id), descriptors);

  // Stored as COLMAP: rows x 6 float32, rows x 128 uint8.
  RawDb raw(path);
  const auto row = raw.Row("SELECT rows, cols, length(data) FROM keypoints");
  EXPECT_EQ(row, (std::vector<std::string>{"3", "6", std::to_string(3 * 6 * 4)}));
  EXPECT_EQ(raw.Row("SELECT rows, cols FROM descriptors"), (std::vector<std::string>{"3", "128"}));

  // Empty feature sets are stored (0 rows) and read back empty.
  db.WriteKeypoints(id, {});
  db.WriteDescriptors(id, FeatureDescriptors(0, 128));
  EXPECT_TRUE(db.ExistsKeypoints(id));
  EXPECT_TRUE(db.ReadKeypoints(id).empty());
  EXPECT_EQ(db.ReadDescriptors(id).rows(), 0);
}

TEST(Database, ReadsTwoAndFourColumnKeypoints) {
  TempDir dir("db");
  const auto path = dir.path() / "database.db";
  {
    Database db(path);
    AddImages(db, 2);
  }
  {
    // Older COLMAP databases: (x, y, scale, orientation) and (x, y).
    RawDb raw(path);
    const float four[] = {1, 2, 3, 0.5f};
    const float two[] = {7, 8, 9, 10};
    sqlite3_stmt* stmt;
    ASSERT_EQ(sqlite3_prepare_v2(raw.get(), "INSERT INTO keypoints VALUES(?, ?, ?, ?)", -1, &stmt,
                                 nullptr),
              SQLITE_OK);
    for (auto [id, rows, cols, data] : {std::tuple{1, 1, 4, four}, std::tuple{2, 2, 2, two}}) {
      sqlite3_bind_int(stmt, 1, id);
      sqlite3_bind_int(stmt, 2, rows);
      sqlite3_bind_int(stmt, 3, cols);
      sqlite3_bind_blob(stmt, 4, data, 16, SQLITE_STATIC);
      ASSERT_EQ(sqlite3_step(stmt), SQLITE_DONE);
      sqlite3_reset(stmt);
    }
    sqlite3_finalize(stmt);
  }
  Database db(path);
  const auto k4 = db.ReadKeypoints(1);
  ASSERT_EQ(k4.size(), 1u);
  EXPECT_FLOAT_EQ(k4[0].x, 1);
  EXPECT_FLOAT_EQ(k4[0].y, 2);
  EXPECT_FLOAT_EQ(k4[0].Scale(), 3);
  EXPECT_FLOAT_EQ(k4[0].Orientation(), 0.5f);
  const auto k2 = db.ReadKeypoints(2);
  ASSERT_EQ(k2.size(), 2u);
  EXPECT_FLOAT_EQ(k2[1].x, 9);
  EXPECT_FLOAT_EQ(k2[1].y, 10);
  EXPECT_FLOAT_EQ(k2[1].Scale(), 1);
}

TEST(Database, CorruptBlobIsAnError) {
  TempDir dir("db");
  const auto path = dir.path() / "database.db";
  {
    Database db(path);
    AddImages(db, 1);
  }
  RawDb(path).Exec("INSERT INTO keypoints VALUES(1, 5, 6, x'0011')");
  Database db(path);
  try {
    db.ReadKeypoints(1);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
}

TEST(Database, MatchesBothOrders) {
  TempDir dir("db");
  const auto path = dir.path() / "database.db";
  Database db(path);
  AddImages(db, 3);
  const FeatureMatches m12 = {{0, 1}, {2, 3}, {4, 5}};
  const FeatureMatches m32 = {{10, 20}, {11, 21}};
  db.WriteMatches(1, 2, m12);
  db.WriteMatches(3, 2, m32);  // stored as pair (2, 3) with columns swapped
  EXPECT_EQ(db.NumMatchedPairs(), 2u);
  EXPECT_TRUE(db.ExistsMatches(2, 1));
  EXPECT_TRUE(db.ExistsMatches(2, 3));
  EXPECT_FALSE(db.ExistsMatches(1, 3));
  EXPECT_TRUE(db.ReadMatches(1, 3).empty());

  EXPECT_EQ(db.ReadMatches(1, 2), m12);
  EXPECT_EQ(db.ReadMatches(2, 1), Swapped(m12));
  EXPECT_EQ(db.ReadMatches(3, 2), m32);
  EXPECT_EQ(db.ReadMatches(2, 3), Swapped(m32));

  RawDb raw(path);
  const auto row = raw.Row("SELECT rows, cols, data FROM matches WHERE pair_id = " +
                           std::to_string(Database::ImagePairToPairId(2, 3)));
  ASSERT_EQ(row.size(), 3u);
  EXPECT_EQ(row[0], "2");
  EXPECT_EQ(row[1], "2");
  EXPECT_EQ(BlobAs<uint32_t>(row[2]), (std::vector<uint32_t>{20, 10, 21, 11}));

  db.WriteMatches(2, 1, {{7, 8}});  // writing again replaces
  EXPECT_EQ(db.ReadMatches(1, 2), (FeatureMatches{{8, 7}}));
  EXPECT_EQ(db.NumMatchedPairs(), 2u);
}

void ExpectNear(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  EXPECT_LT((a - b).norm(), 1e-12 * (1 + b.norm())) << a << "\nvs\n" << b;
}

TEST(Database, TwoViewGeometryBothOrders) {
  TempDir dir("db");
  const auto path = dir.path() / "database.db";
  Database db(path);
  AddImages(db, 4);
  const TwoViewGeometry g = MakeGeometry();
  db.WriteTwoViewGeometry(1, 2, g);
  db.WriteTwoViewGeometry(4, 3, g);  // stored inverted as pair (3, 4)
  TwoViewGeometry failed;            // a pair that failed verification
  failed.config = TwoViewGeometry::kDegenerate;
  db.WriteTwoViewGeometry(1, 3, failed);
  EXPECT_EQ(db.NumVerifiedPairs(), 2u);  // as COLMAP: pairs with inliers
  EXPECT_TRUE(db.ExistsTwoViewGeometry(3, 1));
  EXPECT_FALSE(db.ExistsTwoViewGeometry(2, 4));

  const Eigen::Quaterniond q_inv = g.cam2_from_cam1_rotation.inverse();
  const Eigen::Vector3d t_inv = -(q_inv * g.cam2_from_cam1_translation);
  for (auto [a, b] : {std::pair<image_t, image_t>{1, 2}, {4, 3}}) {
    SCOPED_TRACE(::testing::PrintToString(std::pair{a, b}));
    const TwoViewGeometry same = db.ReadTwoViewGeometry(a, b);
    EXPECT_EQ(same.config, g.config);
    ExpectNear(same.F, g.F);
    ExpectNear(same.E, g.E);
    ExpectNear(same.H, g.H);
    EXPECT_LT(same.cam2_from_cam1_rotation.angularDistance(g.cam2_from_cam1_rotation), 1e-12);
    EXPECT_LT((same.cam2_from_cam1_translation - g.cam2_from_cam1_translation).norm(), 1e-12);
    EXPECT_EQ(same.inlier_matches, g.inlier_matches);

    const TwoViewGeometry other = db.ReadTwoViewGeometry(b, a);
    EXPECT_EQ(other.config, g.config);
    ExpectNear(other.F, g.F.transpose());
    ExpectNear(other.E, g.E.transpose());
    ExpectNear(other.H, g.H.inverse());
    EXPECT_LT(other.cam2_from_cam1_rotation.angularDistance(q_inv), 1e-12);
    EXPECT_LT((other.cam2_from_cam1_translation - t_inv).norm(), 1e-12);
    EXPECT_EQ(other.inlier_matches, Swapped(g.inlier_matches));
  }

  const TwoViewGeometry f = db.ReadTwoViewGeometry(3, 1);
  EXPECT_EQ(f.config, TwoViewGeometry::kDegenerate);
  EXPECT_TRUE(f.inlier_matches.empty());
  EXPECT_TRUE(f.H.isZero());  // no homography stays zero when read swapped, not inf
  EXPECT_EQ(db.ReadTwoViewGeometry(2, 4).config, TwoViewGeometry::kUndefined);

  // COLMAP's layout: row-major F, (w, x, y, z) qvec; pair (3, 4) holds the inverted geometry.
  RawDb raw(path);
  const auto row = raw.Row("SELECT F, qvec, tvec, data FROM two_view_geometries WHERE pair_id = " +
                           std::to_string(Database::ImagePairToPairId(1, 2)));
  ASSERT_EQ(row.size(), 4u);
  const auto F = BlobAs<double>(row[0]);
  ASSERT_EQ(F.size(), 9u);
  EXPECT_EQ(F[1], g.F(0, 1));
  EXPECT_EQ(F[3], g.F(1, 0));
  const auto q = BlobAs<double>(row[1]);
  ASSERT_EQ(q.size(), 4u);
  EXPECT_EQ(q[0], g.cam2_from_cam1_rotation.w());
  EXPECT_EQ(q[1], g.cam2_from_cam1_rotation.x());
  EXPECT_EQ(BlobAs<double>(row[2]).size(), 3u);
  EXPECT_EQ(BlobAs<uint32_t>(row[3]), (std::vector<uint32_t>{0, 5, 1, 7, 4, 2}));
  const auto swapped_row = raw.Row("SELECT F, data FROM two_view_geometries WHERE pair_id = " +
                                   std::to_string(Database::ImagePairToPairId(3, 4)));
  EXPECT_EQ(BlobAs<double>(swapped_row[0])[1], g.F(1, 0));
  EXPECT_EQ(BlobAs<uint32_t>(swapped_row[1]), (std::vector<uint32_t>{5, 0, 7, 1, 2, 4}));

  const auto all = db.ReadAllTwoViewGeometries();
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(all[0].first, Database::ImagePairToPairId(1, 2));
  EXPECT_EQ(all[1].first, Database::ImagePairToPairId(1, 3));
  EXPECT_EQ(all[2].first, Database::ImagePairToPairId(3, 4));
  ExpectNear(all[2].second.F, g.F.transpose());  // COLMAP's order (3, 4)
}

TEST(Database, TransactionRollsBackUnlessCommitted) {
  TempDir dir("db");
  const auto path = dir.path() / "database.db";
  {
    Database db(path);
    {
      Database::Transaction transaction(db);
      AddImages(db, 2);
      db.WriteKeypoints(1, {FeatureKeypoint(1, 2)});
    }  // not committed
    EXPECT_EQ(db.NumImages(), 0u);
    EXPECT_EQ(db.NumCameras(), 0u);
    EXPECT_FALSE(db.ExistsKeypoints(1));

    // An error part-way through a write: nothing of it remains.
    try {
      Database::Transaction transaction(db);
      const camera_t camera = db.WriteCamera(MakeCamera(500));
      db.WriteImage({0, "x.jpg", camera});
      db.WriteImage({0, "x.jpg", camera});  // duplicate name throws
      transaction.Commit();
    } catch (const Error&) {
    }
    EXPECT_EQ(db.NumImages(), 0u);
    EXPECT_EQ(db.NumCameras(), 0u);

    {
      Database::Transaction outer(db);
      AddImages(db, 1);
      {
        Database::Transaction inner(db);  // nested: rolled back alone
        db.WriteMatches(1, 1, {});
        db.WriteCamera(MakeCamera(1));
      }
      EXPECT_EQ(db.NumCameras(), 1u);
      {
        Database::Transaction inner(db);
        db.WriteKeypoints(1, {FeatureKeypoint(3, 4)});
        inner.Commit();
      }
      outer.Commit();
      EXPECT_THROW(outer.Commit(), Error);
    }
  }
  Database db(path);  // the committed writes are in the file
  EXPECT_EQ(db.NumImages(), 1u);
  EXPECT_EQ(db.NumCameras(), 1u);
  EXPECT_EQ(db.NumMatchedPairs(), 0u);
  EXPECT_EQ(db.ReadKeypoints(1).size(), 1u);
}

// ---- Bad paths ----

std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Opening `path` throws a one-line varsfm::Error naming it (and saying `why`).
void ExpectOpenFails(const std::filesystem::path& path, const std::string& why = "") {
  try {
    Database db(path);
    ADD_FAILURE() << "opened " << path;
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_NE(message.find(why), std::string::npos) << message;
  }
}

TEST(Database, BadPathsAreErrorsNamingThePath) {
  TempDir dir("db");
  ExpectOpenFails(dir.path());                              // a folder
  ExpectOpenFails(dir.path() / "missing" / "database.db");  // in a missing folder
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "missing"));

  for (const std::string content :
       {std::string("not a database, just some text\n"), std::string(5000, '\x7f')}) {
    const auto text = dir.path() / "notes.db";
    std::ofstream(text, std::ios::binary) << content;
    ExpectOpenFails(text, "not a database");
    EXPECT_EQ(ReadFile(text), content);  // untouched
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "notes.db-wal"));
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "notes.db-journal"));
  }

  // Another program's SQLite database is not taken over.
  const auto other = dir.path() / "other.db";
  {
    sqlite3* raw = nullptr;
    ASSERT_EQ(sqlite3_open(other.c_str(), &raw), SQLITE_OK);
    sqlite3_exec(raw, "CREATE TABLE notes(x TEXT)", nullptr, nullptr, nullptr);
    sqlite3_close(raw);
  }
  const std::string before = ReadFile(other);
  ExpectOpenFails(other, "not a workspace");
  EXPECT_EQ(ReadFile(other), before);
}

}  // namespace
}  // namespace varsfm
