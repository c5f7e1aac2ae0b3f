#include "varsfm/pipeline/map.h"

#include <algorithm>
#include <future>
#include <map>
#include <optional>
#include <set>
#include <tuple>

#include "varsfm/camera/colmap_models.h"
#include "varsfm/image/image_file.h"
#include "varsfm/io/bundler.h"
#include "varsfm/io/colmap_model.h"
#include "varsfm/io/database.h"
#include "varsfm/io/ply.h"
#include "varsfm/pipeline/output_folder.h"
#include "varsfm/util/atomic_file.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"
#include "varsfm/util/new_folder.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/path_lock.h"
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
  // kShared: one camera per image size. Photos of another size cannot share a camera (its
  // principal point and focal length in pixels are the size's), as COLMAP's single camera
  // requires one size.
  std::map<std::pair<int, int>, camera_t> shared_cameras;
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
    if (options.mapper.intrinsics.sharing == IntrinsicsSharing::kShared) {
      const auto [it, first] =
          shared_cameras.emplace(std::make_pair(camera.width, camera.height), camera.camera_id);
      if (first) rec.AddCamera(camera);
      camera.camera_id = it->second;
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
  const auto geometries = db.ReadAllTwoViewGeometries();
  for (const auto& [pair_id, tvg] : geometries) {
    const auto [id1, id2] = Database::PairIdToImagePair(pair_id);
    if (!ws.graph.ExistsImage(id1) || !ws.graph.ExistsImage(id2)) continue;
    if (tvg.inlier_matches.size() < static_cast<size_t>(options.min_pair_inliers)) continue;
    if (tvg.config == TwoViewGeometry::kDegenerate || tvg.config == TwoViewGeometry::kWatermark ||
        tvg.config == TwoViewGeometry::kUndefined)
      continue;
    const bool planar = tvg.config == TwoViewGeometry::kPlanar ||
                        tvg.config == TwoViewGeometry::kPanoramic ||
                        tvg.config == TwoViewGeometry::kPlanarOrPanoramic;
    if (planar) ws.planar_pairs.push_back({std::min(id1, id2), std::max(id1, id2)});
    // The verified F goes with the matches that are its inliers (a planar pair's are H's), so
    // that the mapper does not estimate it again.
    std::optional<Eigen::Matrix3d> F;
    if (!planar && !tvg.F.isZero()) F = tvg.F;
    ws.graph.AddImagePair(id1, id2, tvg.inlier_matches, F);
    ++pairs;
  }
  // The advice depends on what the workspace holds, not on who ran the matching (`run` has).
  if (geometries.empty())
    Fail("workspace {} has no matched image pair (run `varsfm match` first)",
         options.workspace.string());
  if (pairs == 0)
    Fail(
        "workspace {}: none of the {} matched image pairs has {} or more verified matches (do "
        "the photos overlap?)",
        options.workspace.string(), geometries.size(), options.min_pair_inliers);
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

// One line when photos of the workspace's images could not be read for the colours.
void WarnUnreadPhotos(const KeypointColors& colors, const Reconstruction& images,
                      const std::filesystem::path& image_dir) {
  std::vector<std::string> unread;
  for (const auto& [id, image] : images.images())
    if (!colors.contains(id)) unread.push_back(image.name);
  if (!unread.empty())
    warn("map: {} of {} photos could not be read from {} (first: {}); their points are grey",
         unread.size(), images.images().size(), image_dir.string(), unread.front());
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

// Up to ten image names, then "...".
std::string SomeNames(const std::vector<std::string>& names) {
  std::string text;
  for (size_t i = 0; i < names.size() && i < 10; ++i) text += (i ? ", " : "") + names[i];
  return names.size() > 10 ? text + ", ..." : text;
}

// One line per model (the single-model line when there is one, else with the model's images),
// and a warning naming the images no model holds, each one's reason on a line of its own.
void LogModels(const MultiModelResult& built, size_t num_images, double seconds) {
  for (size_t k = 0; k < built.models.size(); ++k) {
    const Reconstruction& rec = built.models[k].reconstruction;
    std::vector<std::string> names;
    for (const image_t id : rec.RegisteredImageIds()) names.push_back(rec.image(id).name);
    info("map: {}{}/{} images registered, {} points, RMS {:.3f} px{}",
         built.models.size() > 1 ? fmt::format("model {}: ", k) : "", rec.NumRegisteredImages(),
         num_images, rec.points3D().size(), rec.RmsReprojectionError(),
         built.models.size() > 1 ? " (" + SomeNames(names) + ")"
                                 : fmt::format(", {:.2f} s", seconds));
  }
  if (built.unmodelled.empty()) return;
  // The first model built holds every image (multi_model_mapper.h).
  const auto first = std::find_if(built.models.begin(), built.models.end(),
                                  [](const MapperModel& m) { return m.build_order == 0; });
  std::vector<std::string> names;
  for (const UnmodelledImage& u : built.unmodelled)
    names.push_back(first->reconstruction.image(u.image_id).name);
  warn("map: {} of {} images are in no model: {}", names.size(), num_images, SomeNames(names));
  for (size_t i = 0; i < names.size(); ++i)
    info("map: {} is in no model: {}", names[i], built.unmodelled[i].reason);
}

}  // namespace

void MapOptions::Check() const {
  mapper.Check();
  CheckAtLeast("min_pair_inliers", min_pair_inliers, 1);
}

MapSummary RunMapping(const MapOptions& options, OptionsCheck check) {
  if (check == OptionsCheck::kByStage) options.Check();
  // Before the work: a mistyped folder would otherwise leave every point grey without a word.
  if (!options.image_dir.empty() && !std::filesystem::is_directory(options.image_dir))
    Fail("image folder {} does not exist", options.image_dir.string());
  CheckOutputFolderIsOurs(options.output);
  if (!options.image_dir.empty()) CheckOutputOutsideImages(options.output, options.image_dir);
  // The workspace is only read: other maps of it may run at once, a match into it may not.
  std::optional<PathLock> workspace_lock;
  if (std::filesystem::is_regular_file(options.workspace))
    workspace_lock.emplace(options.workspace, LockMode::kShared);
  OutputFolderLock output_lock(options.output);
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
  IncrementalMapperOptions mapper_options = options.mapper;
  const size_t num_images = ws.reconstruction.images().size();
  Progress progress("map", num_images);
  size_t shown = 0;
  mapper_options.progress = [&](size_t registered, size_t, double rms) {
    progress.Tick(registered - shown, fmt::format("registered, RMS {:.3f} px", rms));
    shown = registered;
  };
  Timer mapping;
  MultiModelResult built =
      ReconstructAllModels(std::move(ws.reconstruction), ws.graph, ws.planar_pairs, mapper_options);
  MapSummary result;
  result.seconds_mapping = mapping.Seconds();
  progress.Finish();
  if (built.models.empty()) Fail("map: {}", built.message);

  if (colors.valid()) {
    const KeypointColors keypoint_colors = colors.get();
    WarnUnreadPhotos(keypoint_colors, ws.reconstruction, options.image_dir);
    for (MapperModel& model : built.models) ColorPoints(keypoint_colors, &model.reconstruction);
  }
  const Reconstruction& rec = built.models.front().reconstruction;
  // COLMAP's mapper's layout, OUT/sparse/0, 1, ...: tools that read a COLMAP project find it.
  const auto sparse = options.output / "sparse" / "0";
  // The four outputs are independent readers of the model: written side by side (bundler/ET's
  // take 31 ms one after the other, a tenth of its whole `map`). Each future's get() rethrows
  // its writer's error; the others still finish (a std::async future waits when destroyed).
  // `sparse` (and the output folder above it) exists first, so the text and binary writers
  // each rename their own files into it (WriteFilesAtomically) rather than race to rename a
  // whole folder there.
  output_lock.CreateAndLock();
  RemoveOutputsAfter(options.output, ChainStage::kMap);
  CreateFolder(sparse);
  std::future<void> text =
      std::async(std::launch::async, [&] { WriteColmapModel(rec, sparse, {.binary = false}); });
  std::future<void> bundler = std::async(std::launch::async, [&] {
    WriteBundler(rec, options.output / "bundle.out", options.output / "list.txt");
  });
  WriteColmapModel(rec, sparse, {.binary = true});
  WritePly(rec, options.output / "sparse.ply");
  text.get();
  bundler.get();
  for (size_t k = 1; k < built.models.size(); ++k)
    for (const bool binary : {false, true})
      WriteColmapModel(built.models[k].reconstruction,
                       options.output / "sparse" / std::to_string(k), {.binary = binary});
  RemoveStaleModels(options.output / "sparse", built.models.size());
  result.seconds = total.Seconds();

  nlohmann::json summary = MapSummaryJson(built.models, built.unmodelled);
  const MapperSummary& mapper = built.models.front().summary;
  summary["seconds"] = {{"map_total", result.seconds},
                        {"mapping", result.seconds_mapping},
                        {"initialization", mapper.seconds_initialization},
                        {"registration", mapper.seconds_registration},
                        {"triangulation", mapper.seconds_triangulation},
                        {"local_ba", mapper.seconds_local_ba},
                        {"global_ba", mapper.seconds_global_ba}};
  summary["initial_pair"] = {mapper.initial_image_id1, mapper.initial_image_id2};
  summary["initial_calibration_degenerate"] = mapper.initial_calibration_degenerate;
  // Degenerate pairs that took the prior: the scale of it the third view chose (1: the prior).
  if (mapper.initial_focal_from_prior)
    summary["initial_focal_prior_scale"] = mapper.initial_focal_scale;
  summary["local_bundle_adjustments"] = mapper.num_local_ba;
  summary["global_bundle_adjustments"] = mapper.num_global_ba;
  summary["global_bundle_adjustment_iterations"] = mapper.num_global_ba_iterations;
  summary["two_view_points_removed"] = mapper.num_two_view_points_removed;
  summary["relaxed_registrations"] = mapper.num_relaxed_registrations;
  // Where the photos are, so that later commands (export) need not be told again.
  if (!options.image_dir.empty())
    summary["image_dir"] = std::filesystem::absolute(options.image_dir).string();
  WriteJsonAtomically(options.output / "summary.json", summary);
  LogModels(built, num_images, result.seconds);
  if (built.models.size() > 1)
    info("map: {} models in {}/sparse/0 .. {}, {:.2f} s", built.models.size(),
         options.output.string(), built.models.size() - 1, result.seconds);
  result.mapper = mapper;
  result.num_images = num_images;
  result.reconstruction = std::move(built.models.front().reconstruction);
  result.more_models.assign(std::make_move_iterator(built.models.begin() + 1),
                            std::make_move_iterator(built.models.end()));
  result.unmodelled = std::move(built.unmodelled);
  return result;
}

}  // namespace varsfm
