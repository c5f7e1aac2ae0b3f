#include "varsfm/report/report_data.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>

#include <fmt/format.h>

#include "varsfm/feature/two_view_geometry.h"
#include "varsfm/image/image_list.h"
#include "varsfm/io/colmap_model.h"
#include "varsfm/io/ply_format.h"
#include "varsfm/report/thumbnail.h"
#include "varsfm/scene/reconstruction.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"
#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;

nlohmann::json ReadSummary(const fs::path& file) {
  if (!fs::is_regular_file(file)) return nlohmann::json::object();
  std::ifstream in(file);
  try {
    nlohmann::json summary = nlohmann::json::parse(in);
    if (!summary.is_object()) Fail("{}: not a JSON object", file.string());
    return summary;
  } catch (const nlohmann::json::exception& e) {
    Fail("{}: not valid JSON ({})", file.string(), e.what());
  }
}

// The element counts of a PLY file's header ("vertex", "face"), empty when it cannot be read.
std::map<std::string, size_t> PlyElementCounts(const fs::path& file) {
  std::map<std::string, size_t> counts;
  if (!fs::is_regular_file(file)) return counts;
  std::ifstream in(file, std::ios::binary);
  try {
    for (const ply::Element& element : ply::ReadHeader(in, file).elements)
      counts[element.name] = element.count;
  } catch (const Error& e) {
    warn("report: {}", e.what());
  }
  return counts;
}

std::vector<uint8_t> ReadBytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Per-image and per-observation figures of the model, and the points the 3D view shows.
void AddModelStatistics(const Reconstruction& rec, size_t max_view_points, ReportData* data,
                        std::map<image_t, ReportImage>* images) {
  std::map<image_t, double> sum_squared;
  data->num_points3D = rec.points3D().size();
  const size_t stride = std::max<size_t>(
      1, (rec.points3D().size() + max_view_points - 1) / std::max<size_t>(1, max_view_points));
  size_t index = 0;
  for (const auto& [id, point] : rec.points3D()) {
    data->track_lengths.push_back(point.track.size());
    for (const TrackElement& element : point.track) {
      const double squared = rec.SquaredReprojectionError(element, point.xyz);
      if (!std::isfinite(squared)) continue;  // behind the camera: not an error figure
      data->observation_errors_px.push_back(std::sqrt(squared));
      sum_squared[element.image_id] += squared;
      ++(*images)[element.image_id].num_points3D;
      ++data->num_observations;
    }
    if (index++ % stride == 0 && data->view_points.size() < max_view_points) {
      data->view_points.push_back({static_cast<float>(point.xyz.x()),
                                   static_cast<float>(point.xyz.y()),
                                   static_cast<float>(point.xyz.z())});
      data->view_colors.push_back({point.color[0], point.color[1], point.color[2]});
    }
  }
  for (const auto& [id, image] : rec.images()) {
    ReportImage& out = (*images)[id];
    out.image_id = id;
    out.name = image.name;
    out.registered = image.registered;
    out.camera = rec.camera(image.camera_id);
    out.width = out.camera.width;
    out.height = out.camera.height;
    out.cam_from_world = image.cam_from_world;
    if (out.num_points3D > 0) out.rms_error_px = std::sqrt(sum_squared[id] / out.num_points3D);
  }
}

// Why an image is not in the model: what the mapper recorded in summary.json (another model
// holds it, or its reason), else what the workspace says about it.
std::string FailureReason(const ReportImage& image, const nlohmann::json& summary,
                          bool have_workspace, size_t min_inliers) {
  for (const nlohmann::json& entry : summary.value("images", nlohmann::json::array())) {
    if (!entry.is_object() || entry.value("image_id", kInvalidImageId) != image.image_id) continue;
    const nlohmann::json model = entry.value("model", nlohmann::json());
    if (model.is_number_unsigned() && model.get<size_t>() > 0)
      return fmt::format("in another model: sparse/{} (the mapper could not join it to this one)",
                         model.get<size_t>());
    if (entry.contains("reason") && entry["reason"].is_string())
      return entry["reason"].get<std::string>();
  }
  if (!have_workspace) return "not in the model";
  if (image.image_id == kInvalidImageId)
    return "not extracted (unreadable or too small: see the extract log)";
  if (image.num_keypoints == 0) return "no features extracted";
  if (image.num_verified_pairs == 0) {
    if (image.best_pair_inliers == 0) return "no verified match with any other image";
    return fmt::format("no pair with {}+ verified inliers (best {})", min_inliers,
                       image.best_pair_inliers);
  }
  return fmt::format(
      "matched ({} pairs, best {} inliers) but not registered: too few 2D-3D correspondences "
      "or no pose passed the checks",
      image.num_verified_pairs, image.best_pair_inliers);
}

// Adds the workspace's images, pairs and match counts; false when there is no workspace.
bool AddWorkspace(const fs::path& database, ReportData* data,
                  std::map<image_t, ReportImage>* images) {
  if (!fs::is_regular_file(database)) return false;
  WorkspaceTables tables;
  try {
    tables = ReadWorkspaceTables(database);
  } catch (const Error& e) {
    warn("report: {}; the match figures are left out", e.what());
    return false;
  }
  for (const WorkspaceImageRow& row : tables.images) {
    ReportImage& image = (*images)[row.image_id];
    image.image_id = row.image_id;
    if (image.name.empty()) image.name = row.name;
    if (image.width == 0) {
      image.width = row.width;
      image.height = row.height;
    }
    image.num_keypoints = row.num_keypoints;
  }
  for (const WorkspacePairRow& row : tables.pairs) {
    if (row.num_inliers == 0) continue;
    data->pairs.push_back(row);
    const bool used =
        row.num_inliers >= data->min_pair_inliers && row.config != TwoViewGeometry::kDegenerate &&
        row.config != TwoViewGeometry::kWatermark && row.config != TwoViewGeometry::kUndefined;
    for (const image_t id : {row.image_id1, row.image_id2}) {
      const auto it = images->find(id);
      if (it == images->end()) continue;
      it->second.best_pair_inliers = std::max(it->second.best_pair_inliers, row.num_inliers);
      if (used) ++it->second.num_verified_pairs;
    }
  }
  return true;
}

// Photos of the folder that the workspace never got (skipped by extraction).
void AddUnextractedPhotos(const fs::path& image_dir, std::vector<ReportImage>* images) {
  std::vector<std::string> names;
  try {
    names = ListImages(image_dir, ListingNotes::kQuiet);  // extraction named what it skipped
  } catch (const Error&) {
    return;
  }
  for (const std::string& name : names) {
    const bool known = std::any_of(images->begin(), images->end(),
                                   [&](const ReportImage& image) { return image.name == name; });
    if (known) continue;
    ReportImage image;
    image.name = name;
    images->push_back(std::move(image));
  }
}

// Sub-folders of `sparse` that hold a model (a mapper that splits a scene writes 0, 1, ...).
size_t CountModels(const fs::path& sparse) {
  size_t count = 0;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(sparse, error))
    count += entry.is_directory() && (fs::is_regular_file(entry.path() / "cameras.bin") ||
                                      fs::is_regular_file(entry.path() / "cameras.txt"));
  return count;
}

}  // namespace

const ReportImage* ReportData::FindImage(image_t image_id) const {
  for (const ReportImage& image : images)
    if (image.image_id == image_id) return &image;
  return nullptr;
}

fs::path FindSparseModel(const fs::path& output) {
  for (const fs::path& dir : {output / "sparse" / "0", output / "sparse"}) {
    if (fs::is_regular_file(dir / "cameras.bin") || fs::is_regular_file(dir / "cameras.txt"))
      return dir;
  }
  Fail("{}: no sparse model (sparse/0 or sparse with cameras.bin or cameras.txt)", output.string());
}

void ReportDataOptions::Check() const {
  CheckAtLeast("--max-points", max_view_points, 1);
  CheckInRange("--thumbnail-width", thumbnail_width, 16, 1024);
  CheckInRange("thumbnail_quality", thumbnail_quality, 1, 100);
  model.Check();
}

ReportData CollectReportData(const fs::path& output, const ReportDataOptions& options) {
  if (!fs::is_directory(output)) Fail("{} is not a folder", output.string());
  ReportData data;
  data.output = output;
  data.sparse_dir = FindSparseModel(output);
  data.summary = ReadSummary(output / "summary.json");
  const nlohmann::json models = data.summary.value("models", nlohmann::json());
  data.num_models =
      std::max<size_t>(1, models.is_array() ? models.size() : CountModels(output / "sparse"));

  std::map<image_t, ReportImage> images;
  AddModelStatistics(ReadColmapModel(data.sparse_dir), options.max_view_points, &data, &images);
  const bool have_workspace = AddWorkspace(output / "workspace.db", &data, &images);
  for (auto& [id, image] : images) data.images.push_back(std::move(image));

  fs::path image_dir = options.image_dir;
  if (image_dir.empty() && data.summary.contains("image_dir") &&
      data.summary["image_dir"].is_string())
    image_dir = data.summary["image_dir"].get<std::string>();
  if (have_workspace && !image_dir.empty()) AddUnextractedPhotos(image_dir, &data.images);
  // Extracted photos the report shows without a thumbnail, named in one warning (a photo that
  // was never extracted says why in its row: extract could not read it either).
  std::vector<std::string> without_photo;
  size_t num_extracted = 0;
  for (ReportImage& image : data.images) {
    if (!image.registered)
      image.failure = FailureReason(image, data.summary, have_workspace, data.min_pair_inliers);
    const bool extracted = image.image_id != kInvalidImageId;
    num_extracted += extracted;
    if (image_dir.empty()) continue;
    if (auto thumb = MakeThumbnail(image_dir / image.name, options.thumbnail_width,
                                   options.thumbnail_quality)) {
      image.thumbnail = std::move(thumb->jpeg_base64);
      image.thumbnail_width = thumb->width;
      image.thumbnail_height = thumb->height;
    } else if (extracted) {
      without_photo.push_back(image.name);
    }
  }
  if (!without_photo.empty())
    warn(
        "report: {} of {} photos not found or unreadable in {} (e.g. {}): shown without "
        "thumbnails; --images names the photo folder",
        without_photo.size(), num_extracted, image_dir.string(), without_photo.front());

  const auto dense = PlyElementCounts(output / "dense.ply");
  if (dense.count("vertex")) data.dense_points = dense.at("vertex");
  try {
    data.dense_summary = ReadSummary(output / "dense_summary.json");
  } catch (const Error& e) {
    warn("report: {}; the dense stage's figures are left out", e.what());
  }
  const auto mesh = PlyElementCounts(output / "mesh.ply");
  if (mesh.count("vertex")) data.mesh_vertices = mesh.at("vertex");
  if (mesh.count("face")) data.mesh_faces = mesh.at("face");
  if (options.embed_model && fs::is_regular_file(output / "model.glb")) {
    const std::vector<uint8_t> glb = ReadBytes(output / "model.glb");
    data.glb_file_bytes = glb.size();
    try {
      data.glb = CompactGlbForDisplay(glb, options.model);
    } catch (const Error& e) {
      warn("report: {}; the 3D view shows no textured model", e.what());
    }
  }
  return data;
}

}  // namespace varsfm
