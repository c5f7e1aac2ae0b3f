#pragma once
// The parts of a workspace database (COLMAP's schema) the report shows: every image with its
// size and keypoint count, and the inlier count of every verified pair. Read through a
// read-only SQLite connection with plain queries on the row counts, so the report neither
// loads the match blobs nor can alter a workspace.
#include <filesystem>
#include <string>
#include <vector>

#include "varsfm/util/types.h"

namespace varsfm {

struct WorkspaceImageRow {
  image_t image_id = kInvalidImageId;
  std::string name;
  int width = 0;
  int height = 0;
  size_t num_keypoints = 0;
};

// A verified image pair (two_view_geometries).
struct WorkspacePairRow {
  image_t image_id1 = kInvalidImageId;
  image_t image_id2 = kInvalidImageId;
  size_t num_inliers = 0;
  int config = 0;  // COLMAP's TwoViewGeometry configuration
};

struct WorkspaceTables {
  std::vector<WorkspaceImageRow> images;  // by image id
  std::vector<WorkspacePairRow> pairs;    // by pair id
};

// Throws varsfm::Error (one line naming the file) when `database` cannot be opened or lacks
// COLMAP's tables.
WorkspaceTables ReadWorkspaceTables(const std::filesystem::path& database);

}  // namespace varsfm
