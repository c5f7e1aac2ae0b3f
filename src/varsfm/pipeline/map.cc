#include "varsfm/pipeline/map.h"

#include <algorithm>
#include <fstream>
#include <future>
#include <set>
#include <tuple>

#include "varsfm/camera/colmap_models.h"
#include "varsfm/image/image_file.h"
#include "varsfm/io/bundler.h"
#include "varsfm/io/colmap_model.h"
#include "varsfm/io/database.h"
#include "varsfm/io/ply.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"
#include "varsfm/util/progress.h"
#include "varsfm/util/timer.h"

namespace varsfm {
namespace {

struct LoadedWorkspace {
  Reconstruction reconstruction;  // every image with features, unregistered
  CorrespondenceGraph graph;
  std::vector<std::pair<image_t, image_t>> planar_pairs;
};

LoadedWorkspace LoadWorkspace(const MapOptions& options) {
  if (!std::filesystem::is_regular_file(options.workspace))
    Fail("workspace {} does not exist (run `varsfm extract` and `varsfm match` first)",
         options.workspace.string());
  Database db(options.workspace);
  LoadedWorkspace ws;
  Reconstruction& rec = ws.reconstruction;
  std::optional<Camera> shared_camera;
  for (const DbImage& db_image : db.ReadAllImages()) {
    if (!db.ExistsKeypoints(db_image.image_id)) continue;
    const auto db_camera = db.ReadCamera(db_image.camera_id);
    if (!db_camera)
      Fail("workspace {}: image {} has no camera", options.workspace.string(), db_image.name);
    // Every image starts from its own camera as extracted (prior focal, centred principal
    // point); the shared policy makes all images point at the first one.
    Camera camera = CameraFromColmap(db_camera->model_id, db_camera->params, db_camera->width,
                                     db_camera->height);
    camera.camera_id = db_image.image_id;
    if (options.sharing == IntrinsicsSharing::kShared) {
      if (!shared_camera) {
        shared_camera = camera;
        rec.AddCamera(camera);
      }
      camera.camera_id = shared_camera->camera_id;
    } else {
      rec.AddCamera(camera);
    }
    Image image;
    image.image_id = db_image.image_id;
    image.name = db_image.name;
    image.camera_id = camera.camera_id;
    for (const auto& kp : db.ReadKeypoints(db_image.image_id))
      image.points2D.push_back({Eigen::Vector2d(kp.x, kp.y)});
    ws.graph.AddImage(image.image_id, image.points2D.size());
    rec.AddImage(std::move(image));
  }
  if (rec.images().size() < 2)
    Fail("workspace {} holds {} image(s) with features; at least 2 are needed",
         options.workspace.string(), rec.images().size());

  size_t pairs = 0;
  for (const auto& [pair_id, tvg] : db.ReadAllTwoViewGeometries()) {
    const auto [id1, id2] = Database::PairIdToImagePair(pair_id);
    if (!ws.graph.ExistsImage(id1) || !ws.graph.ExistsImage(id2)) continue;
    if (tvg.inlier_matches.size() < static_cast<size_t>(options.min_pair_inliers)) continue;
    if (tvg.config == TwoViewGeometry::kDegenerate || tvg.config == TwoViewGeometry::kWatermark ||
        tvg.config == TwoViewGeometry::kUndefined)
      continue;
    if (tvg.config == TwoViewGeometry::kPlanar || tvg.config == TwoViewGeometry::kPanoramic ||
        tvg.config == TwoViewGeometry::kPlanarOrPanoramic)
      ws.planar_pairs.push_back({std::min(id1, id2), std::max(id1, id2)});
    ws.graph.AddImagePair(id1, id2, tvg.inlier_matches);
    ++pairs;
  }
  if (pairs == 0)
    Fail("workspace {} has no verified image pair (run `varsfm match` first)",
         options.workspace.string());
  info("map: {} images, {} verified pairs ({} planar/panoramic)", rec.images().size(), pairs,
       ws.planar_pairs.size());
  return ws;
}

// The colour (RGB) of every keypoint of every image that could be read, by image id.
using KeypointColors = std::map<image_t, std::vector<Eigen::Matrix<uint8_t, 3, 1>>>;

// Reads the photographs and samples each keypoint's pixel. RunMapping starts it on a thread of
// its own before mapping: the decoding then overlaps the mapper, whose serial phases leave a
// core free (bundler/ET, 9 photos of 640 x 480: ~35 ms off the wall time). Only the keypoints'
// coordinates are given, so the mapper's reconstruction is never read from this thread.
KeypointColors SampleKeypointColors(
    const std::filesystem::path& image_dir,
    const std::vector<std::tuple<image_t, std::string, std::vector<Eigen::Vector2d>>>& images) {
  KeypointColors colors;
  for (const auto& [id, name, keypoints] : images) {
    cv::Mat bgr;
    try {
      bgr = ReadImagePixels(image_dir / name, ColorMode::kColor);
    } catch (const std::exception&) {
      continue;  // colours are cosmetic: a photo that went missing leaves its points grey
    }
    auto& out = colors[id];
    out.reserve(keypoints.size());
    for (const Eigen::Vector2d& xy : keypoints) {
      const int x = std::clamp(static_cast<int>(xy.x()), 0, bgr.cols - 1);
      const int y = std::clamp(static_cast<int>(xy.y()), 0, bgr.rows - 1);
      const cv::Vec3b c = bgr.at<cv::Vec3b>(y, x);
      out.emplace_back(c[2], c[1], c[0]);
    }
  }
  return colors;
}

// Colours of the 3D points: the mean colour of their observations in the photographs.
void ColorPoints(const KeypointColors& colors, Reconstruction* rec) {
  std::map<point3D_t, Eigen::Vector3d> sums;
  std::map<point3D_t, int> counts;
  for (const image_t id : rec->RegisteredImageIds()) {
    const auto it = colors.find(id);
    if (it == colors.end()) continue;
    const Image& image = rec->image(id);
    for (size_t i = 0; i < image.points2D.size() && i < it->second.size(); ++i) {
      const Point2D& p = image.points2D[i];
      if (!p.HasPoint3D()) continue;
      // try_emplace with Zero: map::operator[] would leave a new Eigen vector uninitialised.
      sums.try_emplace(p.point3D_id, Eigen::Vector3d::Zero()).first->second +=
          it->second[i].cast<double>();
      ++counts[p.point3D_id];
    }
  }
  for (auto& [id, point] : rec->points3D()) {
    const auto it = sums.find(id);
    if (it == sums.end()) continue;
    point.color = (it->second / counts[id]).array().round().cast<uint8_t>();
  }
}

// Removes from OUT/sparse what an earlier run left beside this run's `num_models` models: the
// single-model layout's files in OUT/sparse itself (a reader given OUT/sparse would take them
// for the model) and numbered models beyond this run's.
void RemoveStaleModels(const std::filesystem::path& sparse, size_t num_models) {
  namespace fs = std::filesystem;
  for (const char* name : {"cameras", "images", "points3D"})
    for (const char* extension : {".bin", ".txt"})
      fs::remove(sparse / (name + std::string(extension)));
  for (size_t k = num_models;; ++k) {
    const fs::path stale = sparse / std::to_string(k);
    if (!fs::is_directory(stale)) break;
    fs::remove_all(stale);
  }
}

}  // namespace

nlohmann::json ReconstructionSummaryJson(const Reconstruction& rec) {
  nlohmann::json j;
  j["images_total"] = rec.images().size();
  j["images_registered"] = rec.NumRegisteredImages();
  j["points3D"] = rec.points3D().size();
  j["observations"] = rec.NumObservations();
  j["mean_track_length"] = rec.MeanTrackLength();
  j["rms_reprojection_error_px"] = rec.RmsReprojectionError();
  j["mean_reprojection_error_px"] = rec.MeanReprojectionError();
  nlohmann::json images = nlohmann::json::array();
  for (const auto& [id, image] : rec.images()) {
    nlohmann::json im;
    im["image_id"] = id;
    im["name"] = image.name;
    im["registered"] = image.registered;
    if (image.registered) {
      const Camera& c = rec.camera(image.camera_id);
      im["camera_id"] = image.camera_id;
      im["focal_px"] = c.focal();
      im["aspect"] = c.params[Camera::kAspect];
      im["skew"] = c.params[Camera::kSkew];
      im["principal_point"] = {c.params[Camera::kU0], c.params[Camera::kV0]};
      im["k1"] = c.params[Camera::kK1];
      im["k2"] = c.params[Camera::kK2];
      im["num_points3D"] = image.NumPoints3D();
      const Eigen::Vector3d center = image.Center();
      im["center"] = {center.x(), center.y(), center.z()};
    }
    images.push_back(im);
  }
  j["images"] = images;
  return j;
}

MapResult RunMapping(const MapOptions& options) {
  Timer total;
  LoadedWorkspace ws = LoadWorkspace(options);
  std::future<KeypointColors> colors;
  if (!options.image_dir.empty()) {
    std::vector<std::tuple<image_t, std::string, std::vector<Eigen::Vector2d>>> images;
    for (const auto& [id, image] : ws.reconstruction.images()) {
      std::vector<Eigen::Vector2d> keypoints;
      keypoints.reserve(image.points2D.size());
      for (const Point2D& p : image.points2D) keypoints.push_back(p.xy);
      images.emplace_back(id, image.name, std::move(keypoints));
    }
    colors =
        std::async(std::launch::async, SampleKeypointColors, options.image_dir, std::move(images));
  }
  MapResult result;
  result.reconstruction = std::move(ws.reconstruction);

  IncrementalMapperOptions mapper_options = options.mapper;
  if (options.sharing == IntrinsicsSharing::kFocalPerImage)
    mapper_options.share_all_but_focal = true;
  Progress progress("map", result.reconstruction.images().size());
  size_t shown = 0;
  mapper_options.progress = [&](size_t registered, size_t, double rms) {
    progress.Tick(registered - shown, fmt::format("registered, RMS {:.3f} px", rms));
    shown = registered;
  };
  IncrementalMapper mapper(ws.graph, ws.planar_pairs, mapper_options);
  Timer mapping;
  result.mapper = mapper.Reconstruct(&result.reconstruction);
  result.seconds_mapping = mapping.Seconds();
  progress.Finish();
  if (!result.mapper.success) Fail("map: {}", result.mapper.message);

  Reconstruction& rec = result.reconstruction;
  if (colors.valid()) ColorPoints(colors.get(), &rec);
  // COLMAP's mapper's layout, OUT/sparse/0, 1, ...: tools that read a COLMAP project find it.
  const auto sparse = options.output / "sparse" / "0";
  // The four outputs are independent readers of the model: written side by side (bundler/ET's
  // take 31 ms one after the other, a tenth of its whole `map`). Each future's get() rethrows
  // its writer's error; the others still finish (a std::async future waits when destroyed).
  // `sparse` (and the output folder above it) exists first, so the text and binary writers
  // each rename their own files into it (WriteFilesAtomically) rather than race to rename a
  // whole folder there.
  std::filesystem::create_directories(sparse);
  const Reconstruction& model = rec;
  std::future<void> text =
      std::async(std::launch::async, [&] { WriteColmapModel(model, sparse, {.binary = false}); });
  std::future<void> bundler = std::async(std::launch::async, [&] {
    WriteBundler(model, options.output / "bundle.out", options.output / "list.txt");
  });
  WriteColmapModel(model, sparse, {.binary = true});
  WritePly(model, options.output / "sparse.ply");
  text.get();
  bundler.get();
  RemoveStaleModels(options.output / "sparse", 1);
  result.seconds = total.Seconds();

  nlohmann::json summary = ReconstructionSummaryJson(rec);
  summary["seconds"] = {{"map_total", result.seconds},
                        {"mapping", result.seconds_mapping},
                        {"initialization", result.mapper.seconds_initialization},
                        {"registration", result.mapper.seconds_registration},
                        {"triangulation", result.mapper.seconds_triangulation},
                        {"local_ba", result.mapper.seconds_local_ba},
                        {"global_ba", result.mapper.seconds_global_ba}};
  summary["initial_pair"] = {result.mapper.initial_image_id1, result.mapper.initial_image_id2};
  summary["initial_calibration_degenerate"] = result.mapper.initial_calibration_degenerate;
  // Degenerate pairs that took the prior: the scale of it the third view chose (1: the prior).
  if (result.mapper.initial_focal_from_prior)
    summary["initial_focal_prior_scale"] = result.mapper.initial_focal_scale;
  summary["local_bundle_adjustments"] = result.mapper.num_local_ba;
  summary["global_bundle_adjustments"] = result.mapper.num_global_ba;
  summary["global_bundle_adjustment_iterations"] = result.mapper.num_global_ba_iterations;
  // Where the photos are, so that later commands (export) need not be told again.
  if (!options.image_dir.empty())
    summary["image_dir"] = std::filesystem::absolute(options.image_dir).string();
  std::ofstream(options.output / "summary.json") << summary.dump(2) << "\n";
  info("map: {}/{} images registered, {} points, RMS {:.3f} px, {:.2f} s",
       rec.NumRegisteredImages(), rec.images().size(), rec.points3D().size(),
       rec.RmsReprojectionError(), result.seconds);
  return result;
}

}  // namespace varsfm
