#pragma once
// Prepared SQLite statements for the workspace's tables (io/ only): a Statement prepared once per
// connection, a Query for one use of it, and one-line errors naming the database file.
#include <sqlite3.h>

#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "varsfm/util/error.h"

namespace varsfm::sqlite {

inline std::string PathOf(sqlite3* db) {
  const char* name = sqlite3_db_filename(db, "main");
  return name != nullptr ? name : "";
}

[[noreturn]] inline void FailSql(sqlite3* db, std::string_view what) {
  Fail("{}: {}: {}", PathOf(db), what, sqlite3_errmsg(db));
}

// A statement prepared once for the lifetime of the connection.
class Statement {
 public:
  Statement(sqlite3* db, const char* sql) : db_(db) {
    if (sqlite3_prepare_v3(db, sql, -1, SQLITE_PREPARE_PERSISTENT, &stmt_, nullptr) != SQLITE_OK) {
      FailSql(db, fmt::format("cannot prepare \"{}\"", sql));
    }
  }
  ~Statement() { sqlite3_finalize(stmt_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  sqlite3* db_;
  sqlite3_stmt* stmt_ = nullptr;
};

// One use of a Statement: binds parameters in order, steps, reads columns. The destructor resets
// the statement even when an error is thrown, so no read stays open (it would pin a WAL snapshot
// and make ROLLBACK TO fail).
class Query {
 public:
  Query(Statement& statement, std::string_view what)
      : db_(statement.db_), stmt_(statement.stmt_), what_(what) {}
  ~Query() {
    sqlite3_reset(stmt_);
    sqlite3_clear_bindings(stmt_);
  }
  Query(const Query&) = delete;
  Query& operator=(const Query&) = delete;

  Query& Bind(int64_t value) { return Check(sqlite3_bind_int64(stmt_, ++index_, value)); }
  Query& BindText(const std::string& text) {
    return Check(sqlite3_bind_text(stmt_, ++index_, text.data(), static_cast<int>(text.size()),
                                   SQLITE_TRANSIENT));
  }
  // Empty arrays become zero-length blobs, not NULL, as COLMAP writes them. SQLITE_STATIC: the
  // caller's data outlives the step, which happens before this Query is destroyed.
  Query& BindBlob(const void* data, size_t bytes) {
    if (bytes == 0) return Check(sqlite3_bind_zeroblob(stmt_, ++index_, 0));
    return Check(sqlite3_bind_blob64(stmt_, ++index_, data, bytes, SQLITE_STATIC));
  }

  // True when a row is ready, false when the statement is done.
  bool Step() {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    FailSql(db_, what_);
  }

  // The first row as `from_row(*this)` makes it, or nullopt when the statement yields none.
  template <typename FromRow>
  auto FirstRow(FromRow from_row) -> std::optional<decltype(from_row(*this))> {
    if (!Step()) return std::nullopt;
    return from_row(*this);
  }
  // Every row the statement yields, as `from_row(*this)` makes each.
  template <typename FromRow>
  auto AllRows(FromRow from_row) -> std::vector<decltype(from_row(*this))> {
    std::vector<decltype(from_row(*this))> rows;
    while (Step()) rows.push_back(from_row(*this));
    return rows;
  }

  int64_t Int(int column) const { return sqlite3_column_int64(stmt_, column); }
  std::string Text(int column) const {
    const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(stmt_, column));
    return text != nullptr ? std::string(text, sqlite3_column_bytes(stmt_, column)) : "";
  }
  // The blob as `count` values of T; an empty or NULL blob is read as zero values. A size that
  // disagrees with the row's rows x cols means a corrupt or foreign row. Compared by division:
  // count * sizeof(T) could wrap around to the size of a small blob.
  template <typename T>
  std::vector<T> Array(int column, int64_t count) const {
    const void* data = sqlite3_column_blob(stmt_, column);
    const size_t bytes = static_cast<size_t>(sqlite3_column_bytes(stmt_, column));
    if (count < 0 || bytes % sizeof(T) != 0 || static_cast<uint64_t>(count) != bytes / sizeof(T)) {
      Fail(fmt::format("blob {} has {} bytes, expected {} values of {} bytes",
                       sqlite3_column_name(stmt_, column), bytes, count, sizeof(T)));
    }
    std::vector<T> values(static_cast<size_t>(count));
    if (bytes > 0) std::memcpy(values.data(), data, bytes);
    return values;
  }
  [[noreturn]] void Fail(std::string_view problem) const {
    varsfm::Fail("{}: {}: {}", PathOf(db_), what_, problem);
  }
  // rows x cols of a row's array; a negative or overflowing size is a corrupt row, refused
  // before anything is sized from it.
  int64_t ArraySize(int64_t rows, int64_t cols) const {
    int64_t count = 0;
    if (rows < 0 || cols < 0 || __builtin_mul_overflow(rows, cols, &count))
      Fail(fmt::format("array of {} x {} values", rows, cols));
    return count;
  }
  int64_t Bytes(int column) const { return sqlite3_column_bytes(stmt_, column); }
  bool IsEmpty(int column) const { return Bytes(column) == 0; }

 private:
  Query& Check(int rc) {
    if (rc != SQLITE_OK) FailSql(db_, what_);
    return *this;
  }

  sqlite3* db_;
  sqlite3_stmt* stmt_;
  std::string_view what_;
  int index_ = 0;
};

}  // namespace varsfm::sqlite
