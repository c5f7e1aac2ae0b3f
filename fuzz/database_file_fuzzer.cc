// A whole workspace database file (io/database.cc): opening it (the schema check) and reading
// every camera, image, feature set and pair, as `varsfm map` does. Mutations mostly damage
// SQLite's own pages, which SQLite reports as errors; what reaches varsfm are rows of odd
// types and sizes. The seeds are tiny workspaces written by varsfm::Database.
#include "fuzz_support.h"
#include "varsfm/io/database.h"
#include "varsfm/util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  namespace fs = std::filesystem;
  const fs::path file = varsfm::fuzz::ScratchDir() / "workspace.db";
  std::error_code ec;
  for (const char* suffix : {"-wal", "-shm"}) fs::remove(file.string() + suffix, ec);
  varsfm::fuzz::WriteBytes(file, data, size);
  try {
    const varsfm::Database db(file);
    db.ReadAllCameras();
    for (const varsfm::DbImage& image : db.ReadAllImages()) {
      db.ReadKeypoints(image.image_id);
      db.ReadDescriptors(image.image_id);
    }
    for (const auto& [pair_id, geometry] : db.ReadAllTwoViewGeometries()) {
      const auto [id1, id2] = varsfm::Database::PairIdToImagePair(pair_id);
      db.ReadMatches(id1, id2);
    }
    db.NumMatchedPairs();
    db.NumVerifiedPairs();
  } catch (const varsfm::Error&) {
  }
  return 0;
}
