#pragma once
// Which settings each stored result of the workspace was made with, so that a re-run with other
// settings recomputes what they change instead of silently reusing the old results: per image,
// the settings its features were extracted with; per pair, those its matches and two-view
// geometry were computed with. Kept in tables of varsfm's own beside COLMAP's (varsfm_*; COLMAP
// opens the database and ignores them), created when first needed, so a database that only
// `map` reads keeps exactly COLMAP's schema.
//
// A settings text is compared as a whole: the stage that records it writes only the settings
// that change its results (never thread counts or log levels), in a canonical form.
#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>

#include "varsfm/io/database.h"

namespace varsfm {

class ResultSettings {
 public:
  // Creates the tables if needed. The Database must outlive this object.
  explicit ResultSettings(Database& db);
  ~ResultSettings();
  ResultSettings(const ResultSettings&) = delete;
  ResultSettings& operator=(const ResultSettings&) = delete;

  // The id of `settings` for `stage` ("extract", "match"), recorded when first seen.
  int64_t Id(const std::string& stage, const std::string& settings);

  // image id -> id of the settings its features were extracted with.
  std::unordered_map<image_t, int64_t> ReadImageSettings() const;
  void WriteImageSettings(image_t image_id, int64_t settings_id);

  // image id -> the fingerprint (util/file_fingerprint.h) of the photo its features were
  // extracted from, so that a photo replaced under the same name is extracted again.
  std::unordered_map<image_t, std::string> ReadImageFiles() const;
  void WriteImageFile(image_t image_id, const std::string& fingerprint);

  // pair id (Database::ImagePairToPairId) -> id of the settings the pair was matched with.
  std::unordered_map<image_pair_t, int64_t> ReadPairSettings() const;
  void WritePairSettings(image_t image_id1, image_t image_id2, int64_t settings_id);
  void DeletePairSettings(image_t image_id1, image_t image_id2);

 private:
  struct Statements;
  std::unique_ptr<Statements> statements_;
};

}  // namespace varsfm
