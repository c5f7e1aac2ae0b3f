#pragma once
// The workspace: one SQLite file in COLMAP's database schema (same tables, columns, blob
// layouts and pair-id encoding), so COLMAP can open a varsfm workspace and varsfm can read a
// COLMAP database. Blobs are little-endian row-major arrays: keypoints float32 x 6 (x, y, a11,
// a12, a21, a22; 2- and 4-column blobs are read too), descriptors uint8 x 128, matches and
// inlier matches uint32 x 2, F/E/H double 3x3, qvec double x 4 (w, x, y, z), tvec double x 3,
// camera params double x N.
//
// Every write that belongs together (an image with its camera, keypoints and descriptors; a
// pair's matches and geometry) is done inside one Transaction, so an interrupted run never
// leaves half an image or half a pair behind.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "varsfm/feature/two_view_geometry.h"
#include "varsfm/feature/types.h"
#include "varsfm/util/types.h"

struct sqlite3;

namespace varsfm {

// A row of the cameras table.
struct DbCamera {
  camera_t camera_id = 0;
  int model_id = 0;  // COLMAP camera model id (see camera/colmap_models.h)
  int width = 0;
  int height = 0;
  std::vector<double> params;
  bool has_prior_focal_length = false;
};

// A row of the images table.
struct DbImage {
  image_t image_id = 0;
  std::string name;  // relative to the image folder, '/'-separated
  camera_t camera_id = 0;
};

class Database {
 public:
  // Opens the workspace at `path`, creating the file and COLMAP's tables if needed. Throws
  // varsfm::Error (one line naming the path) if it cannot be opened or is not a database.
  explicit Database(const std::filesystem::path& path);
  ~Database();
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;

  // COLMAP's pair id: image_id1 * 2147483647 + image_id2 with image_id1 < image_id2.
  static image_pair_t ImagePairToPairId(image_t image_id1, image_t image_id2);
  static std::pair<image_t, image_t> PairIdToImagePair(image_pair_t pair_id);
  // True when (id1, id2) must be swapped to match the stored order (id1 > id2).
  static bool SwapImagePair(image_t image_id1, image_t image_id2) { return image_id1 > image_id2; }

  // RAII transaction: commits on Commit(), rolls back if destroyed without it.
  class Transaction {
   public:
    explicit Transaction(Database& db);
    ~Transaction();
    void Commit();

   private:
    Database& db_;
    bool done_ = false;
  };

  // Cameras.
  camera_t WriteCamera(const DbCamera& camera);  // ignores camera.camera_id, returns the new id
  void UpdateCamera(const DbCamera& camera);
  std::optional<DbCamera> ReadCamera(camera_t camera_id) const;
  std::vector<DbCamera> ReadAllCameras() const;
  void DeleteCamera(camera_t camera_id);  // the caller deletes its images first

  // Images.
  image_t WriteImage(const DbImage& image);  // ignores image.image_id, returns the new id
  std::optional<DbImage> ReadImage(image_t image_id) const;
  std::optional<DbImage> ReadImageWithName(const std::string& name) const;
  std::vector<DbImage> ReadAllImages() const;  // sorted by image_id
  // Deletes the image with its keypoints and descriptors (not its camera, nor its pairs).
  void DeleteImage(image_t image_id);

  // Features.
  void WriteKeypoints(image_t image_id, const FeatureKeypoints& keypoints);
  void WriteDescriptors(image_t image_id, const FeatureDescriptors& descriptors);
  bool ExistsKeypoints(image_t image_id) const;
  bool ExistsDescriptors(image_t image_id) const;
  FeatureKeypoints ReadKeypoints(image_t image_id) const;
  FeatureDescriptors ReadDescriptors(image_t image_id) const;

  // Raw matches (before verification). Matches are given for (image_id1, image_id2) and stored
  // in COLMAP's order; reading returns them for the order asked for.
  void WriteMatches(image_t image_id1, image_t image_id2, const FeatureMatches& matches);
  bool ExistsMatches(image_t image_id1, image_t image_id2) const;
  FeatureMatches ReadMatches(image_t image_id1, image_t image_id2) const;
  // Deletes the pair's matches and two-view geometry (no-op for a pair without them).
  void DeletePair(image_t image_id1, image_t image_id2);

  // Verified two-view geometries (inlier matches, config, F, E, H, relative pose). As for
  // matches, F/H/pose are inverted/transposed when read for the swapped order.
  void WriteTwoViewGeometry(image_t image_id1, image_t image_id2, const TwoViewGeometry& tvg);
  bool ExistsTwoViewGeometry(image_t image_id1, image_t image_id2) const;
  TwoViewGeometry ReadTwoViewGeometry(image_t image_id1, image_t image_id2) const;
  // Every stored pair (pair ids in COLMAP's order image_id1 < image_id2).
  std::vector<std::pair<image_pair_t, TwoViewGeometry>> ReadAllTwoViewGeometries() const;

  size_t NumCameras() const;
  size_t NumImages() const;
  size_t NumMatchedPairs() const;
  size_t NumVerifiedPairs() const;

 private:
  friend class ResultSettings;  // varsfm's own tables beside COLMAP's, on this connection
  struct Statements;            // the prepared statements, made once when the database is opened
  void Exec(const char* sql) const;
  sqlite3* db_ = nullptr;
  std::unique_ptr<Statements> statements_;
};

}  // namespace varsfm
