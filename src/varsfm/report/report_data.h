#pragma once
// Everything the report shows, gathered from a run's output folder OUT: summary.json, the sparse
// model (OUT/sparse/0 or OUT/sparse), the workspace (OUT/workspace.db, COLMAP's schema), the
// dense cloud and mesh (OUT/dense.ply, OUT/mesh.ply), the textured model (OUT/model.glb) and
// the photos (thumbnails). Each part is optional except the sparse model: a run stopped early,
// or a folder copied without its workspace, still gets a report of what is there.
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "varsfm/camera/camera.h"
#include "varsfm/geometry/rigid3.h"
#include "varsfm/report/display_model.h"
#include "varsfm/report/workspace_tables.h"
#include "varsfm/util/types.h"

namespace varsfm {

struct ReportImage {
  image_t image_id = kInvalidImageId;
  std::string name;
  int width = 0;  // 0 when neither the model nor the workspace knows the image's size
  int height = 0;
  // From the workspace (0 when it is absent).
  size_t num_keypoints = 0;
  size_t num_verified_pairs = 0;  // pairs the mapper uses (enough inliers, not degenerate)
  size_t best_pair_inliers = 0;
  bool registered = false;
  // Registered images: the estimated camera and pose, and how well the model fits the image.
  Camera camera;
  Rigid3d cam_from_world;
  size_t num_points3D = 0;  // observations of 3D points in this image
  double rms_error_px = 0;  // RMS reprojection error of those observations
  std::string failure;      // unregistered images: why, where known
  std::string thumbnail;    // base64 JPEG, empty when the photo could not be read
  int thumbnail_width = 0;
  int thumbnail_height = 0;
};

struct ReportData {
  std::filesystem::path output;      // OUT
  std::filesystem::path sparse_dir;  // the model read
  size_t num_models = 1;             // models in OUT/sparse (sparse/0, sparse/1, ...)
  nlohmann::json summary = nlohmann::json::object();  // OUT/summary.json, {} when absent
  std::vector<ReportImage> images;                    // by image id: the order of capture
  std::vector<WorkspacePairRow> pairs;                // the verified pairs with at least one inlier
  size_t min_pair_inliers = 15;  // the mapper's default (MapOptions::min_pair_inliers)
  // The sparse model's statistics.
  size_t num_points3D = 0;
  size_t num_observations = 0;
  std::vector<double> observation_errors_px;  // reprojection error of every observation
  std::vector<size_t> track_lengths;          // of every 3D point
  // Points for the 3D view: at most ReportOptions::max_view_points, every k-th in id order.
  std::vector<std::array<float, 3>> view_points;
  std::vector<std::array<uint8_t, 3>> view_colors;
  // Later stages, when their outputs exist.
  std::optional<size_t> dense_points;
  nlohmann::json dense_summary =
      nlohmann::json::object();  // OUT/dense_summary.json, {} when absent
  std::optional<size_t> mesh_vertices;
  std::optional<size_t> mesh_faces;
  // OUT/model.glb made compact for display (display_model.h); empty when absent.
  std::vector<uint8_t> glb;
  size_t glb_file_bytes = 0;  // the size of OUT/model.glb

  const ReportImage* FindImage(image_t image_id) const;
};

struct ReportDataOptions {
  size_t max_view_points = 50000;
  int thumbnail_width = 160;  // pixels; the height follows the photo's aspect
  int thumbnail_quality = 80;
  // Where the photos are; empty: summary.json's image_dir (recorded by map).
  std::filesystem::path image_dir;
  bool embed_model = true;  // read OUT/model.glb
  DisplayModelOptions model;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

// The sparse model folder of OUT: OUT/sparse/0 when it holds a model, else OUT/sparse. Throws
// varsfm::Error (one line) when neither does.
std::filesystem::path FindSparseModel(const std::filesystem::path& output);

// Reads everything above. Throws varsfm::Error (one line naming the file) for a missing or
// unreadable sparse model or summary.json that is not JSON; the other parts are skipped when
// absent (a photo that cannot be read gets no thumbnail).
ReportData CollectReportData(const std::filesystem::path& output, const ReportDataOptions& options);

}  // namespace varsfm
