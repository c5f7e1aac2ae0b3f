#include "varsfm/io/result_settings.h"

#include "varsfm/io/sqlite_statement.h"

namespace varsfm {
namespace {

using sqlite::Query;
using sqlite::Statement;

// An image's row goes with its image (ON DELETE CASCADE); a pair's is deleted with the pair by
// whoever deletes it (COLMAP's pair tables have no foreign key to hang it on).
constexpr const char* kCreateTables[] = {
    "CREATE TABLE IF NOT EXISTS varsfm_settings (settings_id INTEGER PRIMARY KEY AUTOINCREMENT "
    "NOT NULL, stage TEXT NOT NULL, settings TEXT NOT NULL, UNIQUE(stage, settings))",
    "CREATE TABLE IF NOT EXISTS varsfm_image_settings (image_id INTEGER PRIMARY KEY NOT NULL, "
    "settings_id INTEGER NOT NULL, FOREIGN KEY(image_id) REFERENCES images(image_id) ON DELETE "
    "CASCADE, FOREIGN KEY(settings_id) REFERENCES varsfm_settings(settings_id))",
    "CREATE TABLE IF NOT EXISTS varsfm_image_files (image_id INTEGER PRIMARY KEY NOT NULL, "
    "fingerprint TEXT NOT NULL, FOREIGN KEY(image_id) REFERENCES images(image_id) ON DELETE "
    "CASCADE)",
    "CREATE TABLE IF NOT EXISTS varsfm_pair_settings (pair_id INTEGER PRIMARY KEY NOT NULL, "
    "settings_id INTEGER NOT NULL, FOREIGN KEY(settings_id) REFERENCES "
    "varsfm_settings(settings_id))",
};

}  // namespace

struct ResultSettings::Statements {
  explicit Statements(sqlite3* db)
      : add_settings(db, "INSERT OR IGNORE INTO varsfm_settings(stage, settings) VALUES(?, ?)"),
        find_settings(db,
                      "SELECT settings_id FROM varsfm_settings WHERE stage = ? AND settings = ?"),
        read_image_settings(db, "SELECT image_id, settings_id FROM varsfm_image_settings"),
        write_image_settings(db,
                             "INSERT OR REPLACE INTO varsfm_image_settings(image_id, settings_id) "
                             "VALUES(?, ?)"),
        read_image_files(db, "SELECT image_id, fingerprint FROM varsfm_image_files"),
        write_image_file(db,
                         "INSERT OR REPLACE INTO varsfm_image_files(image_id, fingerprint) "
                         "VALUES(?, ?)"),
        read_pair_settings(db, "SELECT pair_id, settings_id FROM varsfm_pair_settings"),
        write_pair_settings(db,
                            "INSERT OR REPLACE INTO varsfm_pair_settings(pair_id, settings_id) "
                            "VALUES(?, ?)"),
        delete_pair_settings(db, "DELETE FROM varsfm_pair_settings WHERE pair_id = ?") {}

  Statement add_settings, find_settings;
  Statement read_image_settings, write_image_settings;
  Statement read_image_files, write_image_file;
  Statement read_pair_settings, write_pair_settings, delete_pair_settings;
};

ResultSettings::ResultSettings(Database& db) {
  Database::Transaction transaction(db);  // all tables or none
  for (const char* sql : kCreateTables) db.Exec(sql);
  transaction.Commit();
  statements_ = std::make_unique<Statements>(db.db_);
}

ResultSettings::~ResultSettings() = default;

int64_t ResultSettings::Id(const std::string& stage, const std::string& settings) {
  Query(statements_->add_settings, "cannot record settings")
      .BindText(stage)
      .BindText(settings)
      .Step();
  Query query(statements_->find_settings, "cannot read settings");
  if (!query.BindText(stage).BindText(settings).Step()) query.Fail("settings not recorded");
  return query.Int(0);
}

std::unordered_map<image_t, int64_t> ResultSettings::ReadImageSettings() const {
  Query query(statements_->read_image_settings, "cannot read the images' settings");
  std::unordered_map<image_t, int64_t> settings;
  while (query.Step()) settings[static_cast<image_t>(query.Int(0))] = query.Int(1);
  return settings;
}

void ResultSettings::WriteImageSettings(image_t image_id, int64_t settings_id) {
  Query(statements_->write_image_settings, "cannot record an image's settings")
      .Bind(image_id)
      .Bind(settings_id)
      .Step();
}

std::unordered_map<image_t, std::string> ResultSettings::ReadImageFiles() const {
  Query query(statements_->read_image_files, "cannot read the images' file fingerprints");
  std::unordered_map<image_t, std::string> files;
  while (query.Step()) files[static_cast<image_t>(query.Int(0))] = query.Text(1);
  return files;
}

void ResultSettings::WriteImageFile(image_t image_id, const std::string& fingerprint) {
  Query(statements_->write_image_file, "cannot record an image's file fingerprint")
      .Bind(image_id)
      .BindText(fingerprint)
      .Step();
}

std::unordered_map<image_pair_t, int64_t> ResultSettings::ReadPairSettings() const {
  Query query(statements_->read_pair_settings, "cannot read the pairs' settings");
  std::unordered_map<image_pair_t, int64_t> settings;
  while (query.Step()) settings[static_cast<image_pair_t>(query.Int(0))] = query.Int(1);
  return settings;
}

void ResultSettings::WritePairSettings(image_t image_id1, image_t image_id2, int64_t settings_id) {
  Query(statements_->write_pair_settings, "cannot record a pair's settings")
      .Bind(static_cast<int64_t>(Database::ImagePairToPairId(image_id1, image_id2)))
      .Bind(settings_id)
      .Step();
}

void ResultSettings::DeletePairSettings(image_t image_id1, image_t image_id2) {
  Query(statements_->delete_pair_settings, "cannot delete a pair's settings")
      .Bind(static_cast<int64_t>(Database::ImagePairToPairId(image_id1, image_id2)))
      .Step();
}

}  // namespace varsfm
