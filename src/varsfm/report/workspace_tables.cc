#include "varsfm/report/workspace_tables.h"

#include <sqlite3.h>

#include <functional>
#include <memory>

#include "varsfm/io/database.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

// Runs `sql` and calls `row` for every result row.
void ForEachRow(sqlite3* db, const std::filesystem::path& file, const char* sql,
                const std::function<void(sqlite3_stmt*)>& row) {
  sqlite3_stmt* statement = nullptr;
  if (sqlite3_prepare_v2(db, sql, -1, &statement, nullptr) != SQLITE_OK) {
    const std::string message = sqlite3_errmsg(db);
    sqlite3_finalize(statement);
    Fail("{}: not a workspace database ({})", file.string(), message);
  }
  int rc = SQLITE_ROW;
  while ((rc = sqlite3_step(statement)) == SQLITE_ROW) row(statement);
  sqlite3_finalize(statement);
  if (rc != SQLITE_DONE) Fail("{}: cannot be read ({})", file.string(), sqlite3_errmsg(db));
}

}  // namespace

WorkspaceTables ReadWorkspaceTables(const std::filesystem::path& database) {
  if (!std::filesystem::is_regular_file(database))
    Fail("workspace {} does not exist", database.string());
  sqlite3* db = nullptr;
  // Only read, but opened read-write where the file allows it (SQLite falls back to read-only
  // where it does not): a workspace is in WAL mode, and a read-only connection that is the last
  // to close leaves the -wal and -shm files it created beside the database, where the user sees
  // them as if a run had been cut off.
  if (sqlite3_open_v2(database.c_str(), &db, SQLITE_OPEN_READWRITE, nullptr) != SQLITE_OK) {
    sqlite3_close_v2(db);
    Fail("{}: cannot open the database", database.string());
  }
  // Closes the connection however the reads end.
  std::unique_ptr<sqlite3, decltype(&sqlite3_close_v2)> closer(db, &sqlite3_close_v2);
  WorkspaceTables tables;
  ForEachRow(db, database,
             "SELECT images.image_id, images.name, cameras.width, cameras.height, "
             "IFNULL(keypoints.rows, 0) FROM images "
             "LEFT JOIN cameras ON images.camera_id = cameras.camera_id "
             "LEFT JOIN keypoints ON images.image_id = keypoints.image_id "
             "ORDER BY images.image_id",
             [&](sqlite3_stmt* s) {
               WorkspaceImageRow row;
               row.image_id = static_cast<image_t>(sqlite3_column_int64(s, 0));
               const auto* name = sqlite3_column_text(s, 1);
               if (name != nullptr) row.name = reinterpret_cast<const char*>(name);
               row.width = sqlite3_column_int(s, 2);
               row.height = sqlite3_column_int(s, 3);
               row.num_keypoints = static_cast<size_t>(sqlite3_column_int64(s, 4));
               tables.images.push_back(std::move(row));
             });
  ForEachRow(db, database, "SELECT pair_id, rows, config FROM two_view_geometries ORDER BY pair_id",
             [&](sqlite3_stmt* s) {
               const auto pair_id = static_cast<image_pair_t>(sqlite3_column_int64(s, 0));
               const auto [id1, id2] = Database::PairIdToImagePair(pair_id);
               tables.pairs.push_back({id1, id2, static_cast<size_t>(sqlite3_column_int64(s, 1)),
                                       sqlite3_column_int(s, 2)});
             });
  return tables;
}

}  // namespace varsfm
