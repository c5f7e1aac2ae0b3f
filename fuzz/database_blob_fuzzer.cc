// The workspace database's row decoding (io/database.cc): keypoint, descriptor, match and
// two-view-geometry blobs with their rows/cols, and camera parameter blobs, as a corrupt or
// foreign (COLMAP) workspace may hold them. One database is opened for the whole run; each input
// is written into it as one row through a second, plain SQLite connection, bypassing varsfm's
// writers, then read back through varsfm::Database.
//
// Input: byte 0 picks the table (mod 5); bytes 1-8 rows (or a camera's width), 9-16 cols (or
// height), 17-20 config (or camera model), all little-endian; the rest is the data blob, then
// F, E, H, qvec, tvec, cut at kPartSeparator.
#include <sqlite3.h>

#include <cstdlib>
#include <cstring>

#include "fuzz_support.h"
#include "varsfm/io/database.h"
#include "varsfm/util/error.h"

namespace {

constexpr size_t kHeaderBytes = 21;

struct Connections {
  std::filesystem::path path = varsfm::fuzz::ScratchDir() / "blobs.db";
  varsfm::Database database{path};
  sqlite3* raw = nullptr;
  Connections() {
    if (sqlite3_open(path.c_str(), &raw) != SQLITE_OK) std::abort();
    sqlite3_exec(raw, "PRAGMA synchronous = OFF", nullptr, nullptr, nullptr);
  }
};

template <typename T>
T Read(const uint8_t* header, size_t at) {
  T value;
  std::memcpy(&value, header + at, sizeof(T));
  return value;
}

// Binds a, b, c to ?1-?3, the blobs to ?4 on, `pair_id` to ?10.
void Insert(sqlite3* db, const char* sql, int64_t a, int64_t b, int64_t c,
            const std::vector<std::string>& blobs, int64_t pair_id = 0) {
  sqlite3_stmt* stmt = nullptr;
  if (sqlite3_prepare_v2(db, sql, -1, &stmt, nullptr) != SQLITE_OK) std::abort();
  sqlite3_bind_int64(stmt, 1, a);
  sqlite3_bind_int64(stmt, 2, b);
  sqlite3_bind_int64(stmt, 3, c);
  for (size_t i = 0; i < blobs.size(); ++i)
    sqlite3_bind_blob64(stmt, static_cast<int>(4 + i), blobs[i].data(), blobs[i].size(),
                        SQLITE_STATIC);
  sqlite3_bind_int64(stmt, 10, pair_id);
  if (sqlite3_step(stmt) != SQLITE_DONE) std::abort();
  sqlite3_finalize(stmt);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static Connections connections;
  uint8_t header[kHeaderBytes] = {};
  std::memcpy(header, data, std::min(size, kHeaderBytes));
  const size_t skip = std::min(size, kHeaderBytes);
  const auto blobs = varsfm::fuzz::SplitParts(data + skip, size - skip, 6);
  const auto rows = Read<int64_t>(header, 1), cols = Read<int64_t>(header, 9);
  const auto config = Read<int32_t>(header, 17);
  const int64_t pair_id = static_cast<int64_t>(varsfm::Database::ImagePairToPairId(1, 2));
  sqlite3* raw = connections.raw;
  const varsfm::Database& db = connections.database;
  try {
    switch (header[0] % 5) {
      case 0:
        Insert(raw, "INSERT OR REPLACE INTO keypoints VALUES(1, ?1, ?2, ?4)", rows, cols, 0,
               {blobs[0]});
        db.ReadKeypoints(1);
        break;
      case 1:
        Insert(raw, "INSERT OR REPLACE INTO descriptors VALUES(1, ?, ?, ?4)", rows, cols, 0,
               {blobs[0]});
        db.ReadDescriptors(1);
        break;
      case 2:
        Insert(raw, "INSERT OR REPLACE INTO matches VALUES(?3, ?1, ?2, ?4)", rows, cols, pair_id,
               {blobs[0]});
        db.ReadMatches(1, 2);
        db.ReadMatches(2, 1);
        break;
      case 3:
        Insert(raw,
               "INSERT OR REPLACE INTO two_view_geometries VALUES(?10, ?1, ?2, ?4, ?3, ?5, ?6, ?7, "
               "?8, ?9)",
               rows, cols, config, blobs, pair_id);
        db.ReadTwoViewGeometry(1, 2);
        db.ReadTwoViewGeometry(2, 1);
        db.ReadAllTwoViewGeometries();
        break;
      default:
        Insert(raw, "INSERT OR REPLACE INTO cameras VALUES(1, ?3, ?1, ?2, ?4, 0)", rows, cols,
               config, {blobs[0]});
        db.ReadCamera(1);
        db.ReadAllCameras();
    }
  } catch (const varsfm::Error&) {
  }
  return 0;
}
