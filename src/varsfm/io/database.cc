#include "varsfm/io/database.h"

#include <sqlite3.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <string_view>
#include <type_traits>
#include <utility>

#include "varsfm/io/sqlite_statement.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"

// Thread safety: a Database is one SQLite connection with shared prepared statements, so one
// object must be used by one thread at a time (parallel stages funnel their writes through one
// thread, or open one Database per thread; SQLite's locking and the busy timeout serialise them).

namespace varsfm {
namespace {

using sqlite::FailSql;
using sqlite::PathOf;
using sqlite::Query;
using sqlite::Statement;

static_assert(std::endian::native == std::endian::little,
              "blobs are little-endian arrays, as COLMAP writes them");
static_assert(sizeof(FeatureKeypoint) == 6 * sizeof(float), "keypoint rows are copied as blobs");
static_assert(sizeof(FeatureMatch) == 2 * sizeof(point2D_t), "match rows are copied as blobs");
static_assert(std::is_trivially_copyable_v<FeatureKeypoint> &&
              std::is_trivially_copyable_v<FeatureMatch>);

constexpr image_pair_t kMaxNumImages = 2147483647;  // COLMAP's pair-id base, 2^31 - 1
constexpr int kColmapUserVersion = 3800;            // what COLMAP 3.8 stores in user_version
constexpr int kBusyTimeoutMs = 30000;  // wait this long for another process's write lock

// COLMAP 3.8's CREATE statements with its exact whitespace: sqlite_master keeps the text as
// written (minus "IF NOT EXISTS"), so a varsfm workspace's schema is byte-identical to COLMAP's.
constexpr const char* kCreateSchema[] = {
    "CREATE TABLE IF NOT EXISTS cameras   (camera_id            INTEGER  PRIMARY KEY "
    "AUTOINCREMENT  NOT NULL,    model                INTEGER                             NOT "
    "NULL,    width                INTEGER                             NOT NULL,    height      "
    "         INTEGER                             NOT NULL,    params               BLOB,    "
    "prior_focal_length   INTEGER                             NOT NULL)",
    "CREATE TABLE IF NOT EXISTS images   (image_id   INTEGER  PRIMARY KEY AUTOINCREMENT  NOT "
    "NULL,    name       TEXT                                NOT NULL UNIQUE,    camera_id  "
    "INTEGER                             NOT NULL,    prior_qw   REAL,    prior_qx   REAL,    "
    "prior_qy   REAL,    prior_qz   REAL,    prior_tx   REAL,    prior_ty   REAL,    prior_tz   "
    "REAL,CONSTRAINT image_id_check CHECK(image_id >= 0 and image_id < 2147483647),FOREIGN "
    "KEY(camera_id) REFERENCES cameras(camera_id))",
    "CREATE UNIQUE INDEX IF NOT EXISTS index_name ON images(name)",
    "CREATE TABLE IF NOT EXISTS keypoints   (image_id  INTEGER  PRIMARY KEY  NOT NULL,    rows    "
    "  INTEGER               NOT NULL,    cols      INTEGER               NOT NULL,    data      "
    "BLOB,FOREIGN KEY(image_id) REFERENCES images(image_id) ON DELETE CASCADE)",
    "CREATE TABLE IF NOT EXISTS descriptors   (image_id  INTEGER  PRIMARY KEY  NOT NULL,    rows  "
    "    INTEGER               NOT NULL,    cols      INTEGER               NOT NULL,    data     "
    " BLOB,FOREIGN KEY(image_id) REFERENCES images(image_id) ON DELETE CASCADE)",
    "CREATE TABLE IF NOT EXISTS matches   (pair_id  INTEGER  PRIMARY KEY  NOT NULL,    rows     "
    "INTEGER               NOT NULL,    cols     INTEGER               NOT NULL,    data     BLOB)",
    "CREATE TABLE IF NOT EXISTS two_view_geometries   (pair_id  INTEGER  PRIMARY KEY  NOT NULL,   "
    " rows     INTEGER               NOT NULL,    cols     INTEGER               NOT NULL,    "
    "data     BLOB,    config   INTEGER               NOT NULL,    F        BLOB,    E        "
    "BLOB,    H        BLOB,    qvec     BLOB,    tvec     BLOB)",
};
constexpr const char* kColmapTables[] = {"cameras",     "images",  "keypoints",
                                         "descriptors", "matches", "two_view_geometries"};

std::string PairName(image_t image_id1, image_t image_id2) {
  return fmt::format("pair ({}, {})", image_id1, image_id2);
}

FeatureMatches SwapMatches(FeatureMatches matches) {
  for (FeatureMatch& match : matches) std::swap(match.point2D_idx1, match.point2D_idx2);
  return matches;
}

// The geometry of the pair seen in the other order: x1^T F^T x2 = 0, x1 ~ H^-1 x2, and
// cam1_from_cam2 = (cam2_from_cam1)^-1.
TwoViewGeometry Inverted(const TwoViewGeometry& geometry) {
  TwoViewGeometry inverted = geometry;
  inverted.F = geometry.F.transpose();
  inverted.E = geometry.E.transpose();
  // A pair without a homography stores H = 0; keep it 0 rather than turning it into inf.
  if (geometry.H.determinant() != 0) inverted.H = geometry.H.inverse();
  inverted.cam2_from_cam1_rotation = geometry.cam2_from_cam1_rotation.inverse();
  inverted.cam2_from_cam1_translation =
      -(inverted.cam2_from_cam1_rotation * geometry.cam2_from_cam1_translation);
  inverted.inlier_matches = SwapMatches(geometry.inlier_matches);
  return inverted;
}

FeatureMatches MatchesFromRow(const Query& query, int rows_column) {
  const int64_t rows = query.Int(rows_column);
  const int64_t cols = query.Int(rows_column + 1);
  if (rows > 0 && cols != 2) query.Fail(fmt::format("{} columns, expected 2", cols));
  const auto values = query.Array<point2D_t>(rows_column + 2, query.ArraySize(rows, cols));
  FeatureMatches matches(static_cast<size_t>(rows));
  if (!values.empty())
    std::memcpy(static_cast<void*>(matches.data()), values.data(),
                values.size() * sizeof(point2D_t));
  return matches;
}

Eigen::Matrix3d Matrix3FromBlob(const Query& query, int column) {
  if (query.IsEmpty(column)) return Eigen::Matrix3d::Zero();  // COLMAP leaves them NULL
  const auto values = query.Array<double>(column, 9);
  return Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(values.data());
}

// Columns from `first`: rows, cols, data, config, F, E, H, qvec, tvec (COLMAP's order).
TwoViewGeometry TwoViewGeometryFromRow(const Query& query, int first) {
  TwoViewGeometry geometry;
  geometry.inlier_matches = MatchesFromRow(query, first);
  geometry.config = static_cast<int>(query.Int(first + 3));
  geometry.F = Matrix3FromBlob(query, first + 4);
  geometry.E = Matrix3FromBlob(query, first + 5);
  geometry.H = Matrix3FromBlob(query, first + 6);
  if (!query.IsEmpty(first + 7)) {
    const auto q = query.Array<double>(first + 7, 4);  // w, x, y, z
    // COLMAP writes a zero quaternion for pairs without a pose; that means "identity".
    if (q[0] != 0 || q[1] != 0 || q[2] != 0 || q[3] != 0) {
      geometry.cam2_from_cam1_rotation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
    }
  }
  if (!query.IsEmpty(first + 8)) {
    const auto t = query.Array<double>(first + 8, 3);
    geometry.cam2_from_cam1_translation = Eigen::Vector3d(t[0], t[1], t[2]);
  }
  return geometry;
}

// Columns: camera_id, model, width, height, params, prior_focal_length.
DbCamera CameraFromRow(const Query& query) {
  DbCamera camera;
  camera.camera_id = static_cast<camera_t>(query.Int(0));
  camera.model_id = static_cast<int>(query.Int(1));
  camera.width = static_cast<int>(query.Int(2));
  camera.height = static_cast<int>(query.Int(3));
  // The cameras table has no rows/cols: the parameter count is the blob size.
  camera.params = query.Array<double>(4, query.Bytes(4) / static_cast<int64_t>(sizeof(double)));
  camera.has_prior_focal_length = query.Int(5) != 0;
  return camera;
}

// Columns: image_id, name, camera_id.
DbImage ImageFromRow(const Query& query) {
  DbImage image;
  image.image_id = static_cast<image_t>(query.Int(0));
  image.name = query.Text(1);
  image.camera_id = static_cast<camera_t>(query.Int(2));
  return image;
}

}  // namespace

struct Database::Statements {
  explicit Statements(sqlite3* db)
      : write_camera(db,
                     "INSERT INTO cameras(model, width, height, params, prior_focal_length) "
                     "VALUES(?, ?, ?, ?, ?)"),
        update_camera(db,
                      "UPDATE cameras SET model = ?, width = ?, height = ?, params = ?, "
                      "prior_focal_length = ? WHERE camera_id = ?"),
        read_camera(db,
                    "SELECT camera_id, model, width, height, params, prior_focal_length FROM "
                    "cameras WHERE camera_id = ?"),
        read_all_cameras(db,
                         "SELECT camera_id, model, width, height, params, prior_focal_length "
                         "FROM cameras ORDER BY camera_id"),
        delete_camera(db, "DELETE FROM cameras WHERE camera_id = ?"),
        write_image(db, "INSERT INTO images(name, camera_id) VALUES(?, ?)"),
        read_image(db, "SELECT image_id, name, camera_id FROM images WHERE image_id = ?"),
        read_image_with_name(db, "SELECT image_id, name, camera_id FROM images WHERE name = ?"),
        read_all_images(db, "SELECT image_id, name, camera_id FROM images ORDER BY image_id"),
        delete_image(db, "DELETE FROM images WHERE image_id = ?"),
        // Writing features or a pair again replaces the row (re-extraction, re-verification).
        write_keypoints(
            db, "INSERT OR REPLACE INTO keypoints(image_id, rows, cols, data) VALUES(?, ?, ?, ?)"),
        write_descriptors(
            db,
            "INSERT OR REPLACE INTO descriptors(image_id, rows, cols, data) VALUES(?, ?, ?, ?)"),
        exists_keypoints(db, "SELECT 1 FROM keypoints WHERE image_id = ?"),
        exists_descriptors(db, "SELECT 1 FROM descriptors WHERE image_id = ?"),
        read_keypoints(db, "SELECT rows, cols, data FROM keypoints WHERE image_id = ?"),
        read_descriptors(db, "SELECT rows, cols, data FROM descriptors WHERE image_id = ?"),
        delete_keypoints(db, "DELETE FROM keypoints WHERE image_id = ?"),
        delete_descriptors(db, "DELETE FROM descriptors WHERE image_id = ?"),
        write_matches(
            db, "INSERT OR REPLACE INTO matches(pair_id, rows, cols, data) VALUES(?, ?, ?, ?)"),
        exists_matches(db, "SELECT 1 FROM matches WHERE pair_id = ?"),
        read_matches(db, "SELECT rows, cols, data FROM matches WHERE pair_id = ?"),
        delete_matches(db, "DELETE FROM matches WHERE pair_id = ?"),
        delete_two_view_geometry(db, "DELETE FROM two_view_geometries WHERE pair_id = ?"),
        write_two_view_geometry(db,
                                "INSERT OR REPLACE INTO two_view_geometries(pair_id, rows, cols, "
                                "data, config, F, E, H, qvec, tvec) "
                                "VALUES(?, ?, ?, ?, ?, ?, ?, ?, ?, ?)"),
        exists_two_view_geometry(db, "SELECT 1 FROM two_view_geometries WHERE pair_id = ?"),
        read_two_view_geometry(db,
                               "SELECT rows, cols, data, config, F, E, H, qvec, tvec FROM "
                               "two_view_geometries WHERE pair_id = ?"),
        read_all_two_view_geometries(db,
                                     "SELECT pair_id, rows, cols, data, config, F, E, H, qvec, "
                                     "tvec FROM two_view_geometries ORDER BY pair_id"),
        count_cameras(db, "SELECT COUNT(*) FROM cameras"),
        count_images(db, "SELECT COUNT(*) FROM images"),
        count_matched_pairs(db, "SELECT COUNT(*) FROM matches"),
        // As COLMAP's NumVerifiedImagePairs: a pair that failed verification has no inliers.
        count_verified_pairs(db, "SELECT COUNT(*) FROM two_view_geometries WHERE rows > 0") {}

  Statement write_camera, update_camera, read_camera, read_all_cameras, delete_camera;
  Statement write_image, read_image, read_image_with_name, read_all_images, delete_image;
  Statement write_keypoints, write_descriptors, exists_keypoints, exists_descriptors;
  Statement read_keypoints, read_descriptors, delete_keypoints, delete_descriptors;
  Statement write_matches, exists_matches, read_matches, delete_matches, delete_two_view_geometry;
  Statement write_two_view_geometry, exists_two_view_geometry, read_two_view_geometry;
  Statement read_all_two_view_geometries;
  Statement count_cameras, count_images, count_matched_pairs, count_verified_pairs;
};

Database::Database(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) Fail("{}: is a folder, not a workspace database", path.string());
  const fs::path parent = path.parent_path();
  if (!parent.empty() && !fs::is_directory(parent, ec)) {
    Fail("{}: cannot create the database: folder {} does not exist", path.string(),
         parent.string());
  }

  // Opening never truncates; SQLite reads the file lazily, so nothing is written before the
  // schema check below has shown that the file is a database.
  if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) !=
      SQLITE_OK) {
    const std::string message = db_ != nullptr ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close_v2(db_);
    db_ = nullptr;
    Fail("{}: cannot open the database: {}", path.string(), message);
  }
  try {
    sqlite3_busy_timeout(db_, kBusyTimeoutMs);

    // The first read: SQLITE_NOTADB here means some other file, which is left as it was.
    std::vector<std::string> tables;
    sqlite3_stmt* list = nullptr;
    int rc = sqlite3_prepare_v2(db_, "SELECT name FROM sqlite_master WHERE type = 'table'", -1,
                                &list, nullptr);
    if (rc == SQLITE_OK) {
      while ((rc = sqlite3_step(list)) == SQLITE_ROW) {
        tables.emplace_back(reinterpret_cast<const char*>(sqlite3_column_text(list, 0)));
      }
    }
    const std::string message = sqlite3_errmsg(db_);
    sqlite3_finalize(list);
    if (rc == SQLITE_NOTADB) Fail("{}: not a database (file left untouched)", path.string());
    if (rc != SQLITE_DONE) Fail("{}: cannot read the database: {}", path.string(), message);
    const auto has = [&](const char* table) {
      return std::find(tables.begin(), tables.end(), table) != tables.end();
    };
    const bool is_new = tables.empty();
    if (!is_new) {
      for (const char* table : kColmapTables) {
        if (!has(table)) {
          Fail("{}: a database without COLMAP's table '{}', not a workspace (left untouched)",
               path.string(), table);
        }
      }
    }

    Exec("PRAGMA foreign_keys = ON");  // off by default in SQLite; the schema relies on them
    // WAL (COLMAP uses it too): commits append to the log instead of rewriting pages through a
    // rollback journal, and readers never block the writer. NORMAL sync is still crash-safe in
    // WAL mode (a power cut may lose the last commits, never corrupt the file). Small
    // transactions, one per image pair, are an order of magnitude cheaper so
    // (docs/measurements.md).
    Exec("PRAGMA journal_mode = WAL");
    Exec("PRAGMA synchronous = NORMAL");

    if (is_new) {
      // All tables in one transaction, so a new workspace has all of them or none.
      Exec("BEGIN");
      try {
        for (const char* sql : kCreateSchema) Exec(sql);
        Exec(fmt::format("PRAGMA user_version = {}", kColmapUserVersion).c_str());
        Exec("COMMIT");
      } catch (...) {
        sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
        throw;
      }
    }
    // Preparing checks every column we use exists (an older COLMAP schema fails here).
    statements_ = std::make_unique<Statements>(db_);
  } catch (...) {
    statements_.reset();
    sqlite3_close_v2(db_);
    db_ = nullptr;
    throw;
  }
}

Database::~Database() {
  statements_.reset();  // finalize before closing, so the close checkpoints and removes the WAL
  if (sqlite3_close_v2(db_) != SQLITE_OK) warn("closing database: {}", sqlite3_errmsg(db_));
}

void Database::Exec(const char* sql) const {
  char* message = nullptr;
  if (sqlite3_exec(db_, sql, nullptr, nullptr, &message) != SQLITE_OK) {
    const std::string text = message != nullptr ? message : sqlite3_errmsg(db_);
    sqlite3_free(message);
    Fail("{}: \"{}\" failed: {}", PathOf(db_), sql, text);
  }
}

image_pair_t Database::ImagePairToPairId(image_t image_id1, image_t image_id2) {
  if (SwapImagePair(image_id1, image_id2)) std::swap(image_id1, image_id2);
  return kMaxNumImages * image_id1 + image_id2;
}

std::pair<image_t, image_t> Database::PairIdToImagePair(image_pair_t pair_id) {
  return {static_cast<image_t>(pair_id / kMaxNumImages),
          static_cast<image_t>(pair_id % kMaxNumImages)};
}

// Savepoints rather than BEGIN/COMMIT, so transactions nest: the outermost RELEASE commits, an
// inner one folds into its parent, and ROLLBACK TO undoes only its own level.
Database::Transaction::Transaction(Database& db) : db_(db) {
  db_.Exec("SAVEPOINT varsfm_transaction");
}

Database::Transaction::~Transaction() {
  if (done_) return;
  // A full disk or an I/O error makes SQLite roll the whole transaction back itself; then no
  // savepoint is left to roll back to, and the connection is in autocommit mode again.
  if (sqlite3_get_autocommit(db_.db_)) return;
  try {
    db_.Exec("ROLLBACK TO varsfm_transaction");
    db_.Exec("RELEASE varsfm_transaction");
  } catch (const Error& e) {
    error("rolling back: {}", e.what());
  }
}

void Database::Transaction::Commit() {
  if (done_) Fail("{}: transaction committed twice", PathOf(db_.db_));
  db_.Exec("RELEASE varsfm_transaction");
  done_ = true;
}

// ---- Cameras ----

camera_t Database::WriteCamera(const DbCamera& camera) {
  Query query(statements_->write_camera, "cannot write a camera");
  query.Bind(camera.model_id).Bind(camera.width).Bind(camera.height);
  query.BindBlob(camera.params.data(), camera.params.size() * sizeof(double));
  query.Bind(camera.has_prior_focal_length ? 1 : 0).Step();
  return static_cast<camera_t>(sqlite3_last_insert_rowid(db_));
}

void Database::UpdateCamera(const DbCamera& camera) {
  Query query(statements_->update_camera, "cannot update a camera");
  query.Bind(camera.model_id).Bind(camera.width).Bind(camera.height);
  query.BindBlob(camera.params.data(), camera.params.size() * sizeof(double));
  query.Bind(camera.has_prior_focal_length ? 1 : 0).Bind(camera.camera_id).Step();
  if (sqlite3_changes(db_) == 0) {
    Fail("{}: cannot update camera {}: no such camera", PathOf(db_), camera.camera_id);
  }
}

std::optional<DbCamera> Database::ReadCamera(camera_t camera_id) const {
  Query query(statements_->read_camera, "cannot read a camera");
  return query.Bind(camera_id).FirstRow(CameraFromRow);
}

std::vector<DbCamera> Database::ReadAllCameras() const {
  return Query(statements_->read_all_cameras, "cannot read the cameras").AllRows(CameraFromRow);
}

void Database::DeleteCamera(camera_t camera_id) {
  Query(statements_->delete_camera, "cannot delete a camera").Bind(camera_id).Step();
}

// ---- Images ----

image_t Database::WriteImage(const DbImage& image) {
  Query query(statements_->write_image, "cannot write an image");
  query.BindText(image.name).Bind(image.camera_id).Step();
  return static_cast<image_t>(sqlite3_last_insert_rowid(db_));
}

std::optional<DbImage> Database::ReadImage(image_t image_id) const {
  Query query(statements_->read_image, "cannot read an image");
  return query.Bind(image_id).FirstRow(ImageFromRow);
}

std::optional<DbImage> Database::ReadImageWithName(const std::string& name) const {
  Query query(statements_->read_image_with_name, "cannot read an image");
  return query.BindText(name).FirstRow(ImageFromRow);
}

std::vector<DbImage> Database::ReadAllImages() const {
  return Query(statements_->read_all_images, "cannot read the images").AllRows(ImageFromRow);
}

void Database::DeleteImage(image_t image_id) {
  // The features explicitly, not through the schema's ON DELETE CASCADE: a database written by
  // another program may hold features whose rows SQLite would not cascade to when that program
  // left foreign keys off (SQLite's default).
  Query(statements_->delete_keypoints, "cannot delete keypoints").Bind(image_id).Step();
  Query(statements_->delete_descriptors, "cannot delete descriptors").Bind(image_id).Step();
  Query(statements_->delete_image, "cannot delete an image").Bind(image_id).Step();
}

// ---- Features ----

void Database::WriteKeypoints(image_t image_id, const FeatureKeypoints& keypoints) {
  Query query(statements_->write_keypoints, "cannot write keypoints");
  query.Bind(image_id).Bind(static_cast<int64_t>(keypoints.size())).Bind(6);
  query.BindBlob(keypoints.data(), keypoints.size() * sizeof(FeatureKeypoint)).Step();
}

void Database::WriteDescriptors(image_t image_id, const FeatureDescriptors& descriptors) {
  Query query(statements_->write_descriptors, "cannot write descriptors");
  query.Bind(image_id).Bind(descriptors.rows()).Bind(descriptors.cols());
  query.BindBlob(descriptors.data(), static_cast<size_t>(descriptors.size())).Step();
}

bool Database::ExistsKeypoints(image_t image_id) const {
  return Query(statements_->exists_keypoints, "cannot read keypoints").Bind(image_id).Step();
}

bool Database::ExistsDescriptors(image_t image_id) const {
  return Query(statements_->exists_descriptors, "cannot read descriptors").Bind(image_id).Step();
}

FeatureKeypoints Database::ReadKeypoints(image_t image_id) const {
  Query query(statements_->read_keypoints, "cannot read keypoints");
  if (!query.Bind(image_id).Step()) return {};
  const int64_t rows = query.Int(0);
  const int64_t cols = query.Int(1);
  const auto values = query.Array<float>(2, query.ArraySize(rows, cols));
  // Checked before sizing: with 0 columns any number of rows fits an empty blob.
  if (rows > 0 && cols != 2 && cols != 4 && cols != 6)
    query.Fail(fmt::format("image {}: {} columns, expected 2, 4 or 6", image_id, cols));
  FeatureKeypoints keypoints(static_cast<size_t>(rows));
  for (size_t i = 0; i < keypoints.size(); ++i) {
    const float* row = values.data() + i * cols;
    // COLMAP writes 6 columns (affine shape); older databases have 4 (x, y, scale, orientation)
    // or 2 (x, y).
    switch (cols) {
      case 6:
        keypoints[i] = FeatureKeypoint(row[0], row[1]);
        keypoints[i].a11 = row[2];
        keypoints[i].a12 = row[3];
        keypoints[i].a21 = row[4];
        keypoints[i].a22 = row[5];
        break;
      case 4:
        keypoints[i] = FeatureKeypoint(row[0], row[1], row[2], row[3]);
        break;
      case 2:
        keypoints[i] = FeatureKeypoint(row[0], row[1]);
        break;
      default:  // refused above
        break;
    }
  }
  return keypoints;
}

FeatureDescriptors Database::ReadDescriptors(image_t image_id) const {
  Query query(statements_->read_descriptors, "cannot read descriptors");
  if (!query.Bind(image_id).Step()) return {};
  const int64_t rows = query.Int(0);
  const int64_t cols = query.Int(1);
  const auto values = query.Array<uint8_t>(2, query.ArraySize(rows, cols));
  FeatureDescriptors descriptors(rows, cols);
  if (!values.empty()) std::memcpy(descriptors.data(), values.data(), values.size());
  return descriptors;
}

// ---- Matches ----

namespace {

// The pair_id column of the pair (image_id1, image_id2), in either order.
int64_t PairIdOf(image_t image_id1, image_t image_id2) {
  return static_cast<int64_t>(Database::ImagePairToPairId(image_id1, image_id2));
}

// A match list's rows, cols and data columns, as MatchesFromRow reads them.
void BindMatches(Query& query, const FeatureMatches& matches) {
  query.Bind(static_cast<int64_t>(matches.size())).Bind(2);
  query.BindBlob(matches.data(), matches.size() * sizeof(FeatureMatch));
}

// Whether the pair's row exists in the table `exists` queries.
bool PairRowExists(Statement& exists, std::string_view what, image_t image_id1, image_t image_id2) {
  return Query(exists, what).Bind(PairIdOf(image_id1, image_id2)).Step();
}

// The pair's row as `from_row` reads it, turned by `swap` when it is stored from image_id2 to
// image_id1 (SwapImagePair); empty when the pair has no row.
template <typename FromRow, typename Swap>
auto ReadPairRow(Statement& read, std::string_view what, image_t image_id1, image_t image_id2,
                 FromRow from_row, Swap swap) -> decltype(from_row(std::declval<const Query&>())) {
  Query query(read, what);
  if (!query.Bind(PairIdOf(image_id1, image_id2)).Step()) return {};
  auto row = from_row(query);
  return Database::SwapImagePair(image_id1, image_id2) ? swap(std::move(row)) : row;
}

}  // namespace

void Database::WriteMatches(image_t image_id1, image_t image_id2, const FeatureMatches& matches) {
  const std::string what = "cannot write matches of " + PairName(image_id1, image_id2);
  const FeatureMatches stored =
      SwapImagePair(image_id1, image_id2) ? SwapMatches(matches) : matches;
  Query query(statements_->write_matches, what);
  query.Bind(PairIdOf(image_id1, image_id2));
  BindMatches(query, stored);
  query.Step();
}

bool Database::ExistsMatches(image_t image_id1, image_t image_id2) const {
  return PairRowExists(statements_->exists_matches, "cannot read matches", image_id1, image_id2);
}

FeatureMatches Database::ReadMatches(image_t image_id1, image_t image_id2) const {
  return ReadPairRow(
      statements_->read_matches, "cannot read matches of " + PairName(image_id1, image_id2),
      image_id1, image_id2, [](const Query& row) { return MatchesFromRow(row, 0); },
      [](FeatureMatches matches) { return SwapMatches(std::move(matches)); });
}

void Database::DeletePair(image_t image_id1, image_t image_id2) {
  const auto pair_id = PairIdOf(image_id1, image_id2);
  Query(statements_->delete_matches, "cannot delete matches").Bind(pair_id).Step();
  Query(statements_->delete_two_view_geometry, "cannot delete a two-view geometry")
      .Bind(pair_id)
      .Step();
}

// ---- Two-view geometries ----

void Database::WriteTwoViewGeometry(image_t image_id1, image_t image_id2,
                                    const TwoViewGeometry& tvg) {
  const std::string what = "cannot write the geometry of " + PairName(image_id1, image_id2);
  const TwoViewGeometry stored = SwapImagePair(image_id1, image_id2) ? Inverted(tvg) : tvg;
  // Row-major 3x3 blobs and (w, x, y, z), as COLMAP stores them.
  const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> F = stored.F, E = stored.E, H = stored.H;
  const Eigen::Quaterniond& q = stored.cam2_from_cam1_rotation;
  const double qvec[4] = {q.w(), q.x(), q.y(), q.z()};
  const Eigen::Vector3d& tvec = stored.cam2_from_cam1_translation;

  Query query(statements_->write_two_view_geometry, what);
  query.Bind(PairIdOf(image_id1, image_id2));
  BindMatches(query, stored.inlier_matches);
  query.Bind(stored.config);
  query.BindBlob(F.data(), sizeof(double) * 9).BindBlob(E.data(), sizeof(double) * 9);
  query.BindBlob(H.data(), sizeof(double) * 9).BindBlob(qvec, sizeof(qvec));
  query.BindBlob(tvec.data(), sizeof(double) * 3).Step();
}

bool Database::ExistsTwoViewGeometry(image_t image_id1, image_t image_id2) const {
  return PairRowExists(statements_->exists_two_view_geometry, "cannot read a two-view geometry",
                       image_id1, image_id2);
}

TwoViewGeometry Database::ReadTwoViewGeometry(image_t image_id1, image_t image_id2) const {
  return ReadPairRow(
      statements_->read_two_view_geometry,
      "cannot read the geometry of " + PairName(image_id1, image_id2), image_id1, image_id2,
      [](const Query& row) { return TwoViewGeometryFromRow(row, 0); },
      [](const TwoViewGeometry& geometry) { return Inverted(geometry); });
}

std::vector<std::pair<image_pair_t, TwoViewGeometry>> Database::ReadAllTwoViewGeometries() const {
  Query query(statements_->read_all_two_view_geometries, "cannot read the two-view geometries");
  return query.AllRows([](const Query& row) {
    return std::pair(static_cast<image_pair_t>(row.Int(0)), TwoViewGeometryFromRow(row, 1));
  });
}

// ---- Counts ----

namespace {
size_t Count(Statement& statement) {
  Query query(statement, "cannot count rows");
  query.Step();
  return static_cast<size_t>(query.Int(0));
}
}  // namespace

size_t Database::NumCameras() const { return Count(statements_->count_cameras); }
size_t Database::NumImages() const { return Count(statements_->count_images); }
size_t Database::NumMatchedPairs() const { return Count(statements_->count_matched_pairs); }
size_t Database::NumVerifiedPairs() const { return Count(statements_->count_verified_pairs); }

}  // namespace varsfm
