#include "varsfm/pipeline/extract.h"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>
#include <nlohmann/json.hpp>

#include "varsfm/camera/colmap_models.h"
#include "varsfm/feature/mat_buffer_pool.h"
#include "varsfm/image/image_io.h"
#include "varsfm/image/image_list.h"
#include "varsfm/io/database.h"
#include "varsfm/io/result_settings.h"
#include "varsfm/pipeline/video_frames.h"
#include "varsfm/util/byte_budget.h"
#include "varsfm/util/error.h"
#include "varsfm/util/file_fingerprint.h"
#include "varsfm/util/log.h"
#include "varsfm/util/new_folder.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/path_lock.h"
#include "varsfm/util/progress.h"
#include "varsfm/util/timer.h"
#include "varsfm/util/usable_memory.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;

// COLMAP's default focal length when nothing is known (feature_extraction.cc).
constexpr double kDefaultFocalFactor = 1.2;

// Reads an image for extraction, or warns (one line naming the file) and returns nothing when
// it is unreadable or too small to hold useful features.
std::optional<Photo> LoadUsableImage(const fs::path& path, int min_size) {
  try {
    Photo image = ReadPhoto(path, ColorMode::kGray);
    if (std::min(image.width(), image.height()) < min_size) {
      warn("skipping {}: {}x{} pixels is too small (minimum {})", path.string(), image.width(),
           image.height(), min_size);
      return std::nullopt;
    }
    return image;
  } catch (const Error& e) {
    warn("skipping: {}", e.what());
    return std::nullopt;
  }
}

DbCamera DefaultCamera(const Photo& image) {
  DbCamera camera;
  camera.model_id = kColmapSimpleRadial;
  camera.width = image.width();
  camera.height = image.height();
  camera.has_prior_focal_length = image.exif_focal_px.has_value();
  const double focal =
      image.exif_focal_px.value_or(kDefaultFocalFactor * std::max(image.width(), image.height()));
  // COLMAP's pixel convention puts the image centre at (w/2, h/2).
  camera.params = {focal, image.width() / 2.0, image.height() / 2.0, 0.0};
  return camera;
}

// What one image of the parallel stage hands to the writer.
struct Extracted {
  size_t index = 0;
  bool usable = false;
  DbCamera camera;
  ImageFeatures features;
  std::string fingerprint;  // of the photo's file
};

struct InputImages {
  fs::path dir;
  std::vector<std::string> names;
  std::string video_folder;  // video input: the names' folder, with its trailing '/'
};

InputImages ListInput(const ExtractOptions& options, ExtractSummary& summary) {
  const bool has_images = !options.image_dir.empty();
  const bool has_video = !options.video.empty();
  if (has_images == has_video) Fail("give exactly one of an image folder and a video");
  InputImages input;
  if (has_images) {
    input.dir = options.image_dir;
    input.names = ListImages(options.image_dir);
    if (input.names.empty()) Fail("no image files in {}", options.image_dir.string());
  } else {
    input.dir = VideoFramesDir(options.workspace);
    KeyframeSummary keyframes =
        ExtractVideoFrames(options.workspace, options.video, options.keyframes);
    summary.video_frames = keyframes.frames_read;
    summary.video_blurred = keyframes.frames_blurred;
    summary.video_announced = keyframes.frames_announced;
    info("video {}: {} frames, {} blurred, {} keyframes in {}", options.video.string(),
         keyframes.frames_read, keyframes.frames_blurred, keyframes.names.size(),
         input.dir.string());
    if (keyframes.names.empty()) Fail("no sharp frame in video {}", options.video.string());
    input.names = std::move(keyframes.names);
    input.video_folder = input.names[0].substr(0, input.names[0].find('/') + 1);
  }
  return input;
}

// The settings that change an image's features, in a canonical text (sorted keys): a
// re-extraction with other ones extracts again. Thread counts are left out on purpose. The
// extractor's version is one of them: features of an older extractor (another version, or none
// recorded) are extracted again.
std::string FeatureSettings(const SiftOptions& sift) {
  nlohmann::json settings;
  settings["extractor_version"] = kSiftExtractorVersion;
  settings["max_features"] = sift.max_features;
  settings["max_image_size"] = sift.max_image_size;
  settings["contrast_threshold"] = sift.contrast_threshold;
  settings["edge_threshold"] = sift.edge_threshold;
  return settings.dump();
}

// Photos in flight in the extraction's pipeline: two per thread, but where `budget` bytes do not
// hold a scale space of `photo_bytes` for each thread, as many as it holds (at least one): the
// threads left idle then serve OpenCV's parallel loops inside those photos' SIFT.
size_t PhotosInFlight(size_t threads, size_t photo_bytes, size_t budget) {
  const size_t fit = photo_bytes > 0 && budget > 0 ? budget / photo_bytes : 2 * threads;
  return fit >= threads ? 2 * threads : std::max<size_t>(1, fit);
}

// What a run does with each input image, given what the workspace holds.
struct ExtractionPlan {
  std::vector<size_t> todo;  // indices into the input names, to extract
  // Names already in the workspace whose features this run writes (again): those without
  // features (e.g. imported) and those extracted with other settings.
  std::unordered_map<std::string, image_t> existing;
  size_t num_existing = 0;  // skipped: extracted with these settings
};

// Images with features from these settings are skipped, unless their photo is another file than
// the one they were extracted from (a photo replaced or resized under the same name). Features
// with no record (made by COLMAP or an earlier varsfm) are kept and recorded as made with these
// settings and from the photo there now: nothing tells what they were made from, and a user
// resuming expects them kept.
ExtractionPlan PlanExtraction(Database& db, ResultSettings& record, int64_t settings,
                              const InputImages& input, const std::vector<bool>& unusable) {
  const std::vector<std::string>& names = input.names;
  const std::unordered_map<image_t, int64_t> recorded = record.ReadImageSettings();
  std::unordered_map<std::string, image_t> current, stale, without_features;
  std::vector<image_t> unrecorded;
  for (const DbImage& image : db.ReadAllImages()) {
    if (!db.ExistsKeypoints(image.image_id)) {
      without_features[image.name] = image.image_id;
      continue;
    }
    const auto it = recorded.find(image.image_id);
    if (it == recorded.end()) unrecorded.push_back(image.image_id);
    (it == recorded.end() || it->second == settings ? current : stale)[image.name] = image.image_id;
  }
  if (!unrecorded.empty()) {
    Database::Transaction transaction(db);
    for (const image_t image_id : unrecorded) record.WriteImageSettings(image_id, settings);
    transaction.Commit();
    info("{} images have features of unrecorded settings (COLMAP's or an earlier varsfm's): kept",
         unrecorded.size());
  }

  ExtractionPlan plan;
  size_t num_stale = 0, num_replaced = 0;
  const std::unordered_map<image_t, std::string> files = record.ReadImageFiles();
  std::vector<std::pair<image_t, std::string>> unrecorded_files;
  for (size_t i = 0; i < names.size(); ++i) {
    if (const auto it = current.find(names[i]); it != current.end()) {
      const std::string fingerprint = FileFingerprint(input.dir / names[i]);
      const auto file = files.find(it->second);
      if (file == files.end()) unrecorded_files.emplace_back(it->second, fingerprint);
      if (file == files.end() || file->second == fingerprint || unusable[i]) {
        ++plan.num_existing;
        continue;
      }
      plan.todo.push_back(i);
      plan.existing[names[i]] = it->second;
      ++num_replaced;
      continue;
    }
    if (unusable[i]) continue;
    plan.todo.push_back(i);
    if (const auto it = stale.find(names[i]); it != stale.end()) {
      plan.existing[names[i]] = it->second;
      ++num_stale;
    } else if (const auto it2 = without_features.find(names[i]); it2 != without_features.end()) {
      plan.existing[names[i]] = it2->second;
    }
  }
  if (!unrecorded_files.empty()) {
    Database::Transaction transaction(db);
    for (const auto& [image_id, fingerprint] : unrecorded_files)
      record.WriteImageFile(image_id, fingerprint);
    transaction.Commit();
  }
  if (plan.num_existing > 0) {
    info("{} of {} images already extracted, skipped", plan.num_existing, names.size());
  }
  if (num_replaced > 0) {
    info(
        "{} images are other files than the ones extracted under their names: extracting them "
        "again (their matches are removed)",
        num_replaced);
  }
  if (num_stale > 0) {
    info(
        "{} images were extracted with other settings: extracting them again (their matches "
        "are removed)",
        num_stale);
  }
  return plan;
}

// Keyframes of the video that an earlier extraction chose and this one did not (other keyframe
// settings) are stale: their images leave the workspace with their pairs, and their files go
// (the keyframe cap may have removed them already).
void RemoveEarlierKeyframes(Database& db, ResultSettings& record, const InputImages& input) {
  if (input.video_folder.empty()) return;
  const std::unordered_set<std::string> keyframes(input.names.begin(), input.names.end());
  const std::vector<DbImage> images = db.ReadAllImages();
  std::vector<DbImage> stale;
  for (const DbImage& image : images) {
    if (image.name.starts_with(input.video_folder) && !keyframes.contains(image.name)) {
      stale.push_back(image);
    }
  }
  if (stale.empty()) return;
  Database::Transaction transaction(db);
  for (const DbImage& image : stale) {
    for (const DbImage& other : images) {
      if (other.image_id == image.image_id) continue;
      db.DeletePair(image.image_id, other.image_id);
      record.DeletePairSettings(image.image_id, other.image_id);
    }
    db.DeleteImage(image.image_id);
    db.DeleteCamera(image.camera_id);
  }
  transaction.Commit();
  std::error_code ec;
  for (const DbImage& image : stale) fs::remove(input.dir / image.name, ec);
  info("{} keyframes chosen by an earlier extraction with other keyframe settings removed",
       stale.size());
}

// Removes `images` and their cameras, in one transaction (best effort: this runs while an error
// is on its way out, and reports its own failure only in the log).
void RemoveImages(Database& db, const std::vector<DbImage>& images) {
  if (images.empty()) return;
  try {
    Database::Transaction transaction(db);
    for (const DbImage& image : images) {
      db.DeleteImage(image.image_id);
      db.DeleteCamera(image.camera_id);
    }
    transaction.Commit();
    warn("removed the {} images this run had added", images.size());
  } catch (const Error& e) {
    error("cannot remove the images this run added: {}", e.what());
  }
}

// True when the two files hold the same bytes.
bool SameContents(const fs::path& a, const fs::path& b) {
  std::ifstream fa(a, std::ios::binary), fb(b, std::ios::binary);
  if (!fa || !fb) return false;
  return std::equal(std::istreambuf_iterator<char>(fa), std::istreambuf_iterator<char>(),
                    std::istreambuf_iterator<char>(fb), std::istreambuf_iterator<char>());
}

// Photos of the input that are one file under two names (a copy): the copy adds no view, and the
// two make a pair without a baseline. A warning per copy, the first name by name order kept as
// the original; the run goes on. Fingerprints (util/file_fingerprint.h) find the candidates, a
// comparison of the whole files confirms them.
void WarnOfCopies(const Database& db, const ResultSettings& record, const InputImages& input) {
  const std::unordered_set<std::string> names(input.names.begin(), input.names.end());
  const std::unordered_map<image_t, std::string> files = record.ReadImageFiles();
  std::vector<std::pair<std::string, std::string>> photos;  // name, fingerprint
  for (const DbImage& image : db.ReadAllImages()) {
    const auto file = files.find(image.image_id);
    if (names.count(image.name) && file != files.end())
      photos.emplace_back(image.name, file->second);
  }
  std::sort(photos.begin(), photos.end());
  std::unordered_map<std::string, std::vector<std::string>> originals;  // by fingerprint
  for (const auto& [name, fingerprint] : photos) {
    std::vector<std::string>& same_fingerprint = originals[fingerprint];
    const auto original = std::find_if(same_fingerprint.begin(), same_fingerprint.end(),
                                       [&](const std::string& other) {
                                         return SameContents(input.dir / other, input.dir / name);
                                       });
    if (original == same_fingerprint.end()) {
      same_fingerprint.push_back(name);
    } else {
      warn("{} is the same file as {} (a copy?): it adds no view to the model", name, *original);
    }
  }
}

void RemoveWorkspace(const fs::path& workspace) {
  std::error_code ec;
  for (const char* suffix : {"", "-wal", "-shm", "-journal"}) {
    fs::remove(workspace.string() + suffix, ec);
  }
}

// Extracts the features of the input's usable images into `db`, skipping those it holds
// already. If it fails, the images it added are removed again when `undo_on_failure` (a
// workspace the run created is removed whole instead; undoing first only failed again on a
// full disk).
void WriteFeatures(Database& db, const ExtractOptions& options, const InputImages& input,
                   size_t first_index, std::optional<Photo> first_image,
                   const std::vector<bool>& unusable, ExtractSummary& summary,
                   bool undo_on_failure) {
  std::vector<DbImage> added;  // image and camera ids written by this run
  ResultSettings record(db);
  const int64_t settings = record.Id("extract", FeatureSettings(options.sift));
  RemoveEarlierKeyframes(db, record, input);
  const ExtractionPlan plan = PlanExtraction(db, record, settings, input, unusable);
  summary.num_existing = plan.num_existing;
  const std::vector<size_t>& todo = plan.todo;
  const std::vector<image_t> all_ids = [&db] {
    std::vector<image_t> ids;
    for (const DbImage& image : db.ReadAllImages()) ids.push_back(image.image_id);
    return ids;
  }();

  // The first photo's scale space sets how many photos are in flight (a set's photos share a
  // size, mostly); a photo of another camera takes its own scale space's bytes from the budget
  // while it is extracted, and waits where they do not fit beside the others'.
  const size_t photo_bytes = first_image ? SiftMemoryBytes(first_image->pixels.cols,
                                                           first_image->pixels.rows, options.sift)
                                         : 0;
  const size_t budget = options.memory_mb > 0 ? options.memory_mb << 20 : UsableMemoryBytes() / 2;
  ByteBudget scale_spaces(budget);
  Progress progress("extract", todo.size());
  const auto extract = [&](size_t index) {
    Extracted out;
    out.index = index;
    std::optional<Photo> image;
    if (index == first_index) {
      image = std::move(first_image);
    } else {
      image = LoadUsableImage(input.dir / input.names[index], options.min_image_size);
    }
    if (!image) return out;
    out.usable = true;
    out.fingerprint = FileFingerprint(input.dir / input.names[index]);
    out.camera = DefaultCamera(*image);
    const ByteBudget::Lease lease =
        scale_spaces.Acquire(SiftMemoryBytes(image->pixels.cols, image->pixels.rows, options.sift));
    // Isolated: while SIFT's parallel loops wait, this thread takes none of the pipeline's other
    // photos, whose wait for the budget would then hold this photo's lease for ever.
    out.features =
        tbb::this_task_arena::isolate([&] { return ExtractSift(image->pixels, options.sift); });
    return out;
  };
  const auto write = [&](const Extracted& item) {
    const std::string& name = input.names[item.index];
    if (!item.usable) {
      ++summary.num_unusable;
      progress.Tick(1, name);
      return;
    }
    const size_t count = item.features.keypoints.size();
    if (count < static_cast<size_t>(options.min_features)) {
      warn("image {} has only {} features (featureless?); it may not register", name, count);
    }
    Database::Transaction transaction(db);
    image_t image_id;
    if (const auto it = plan.existing.find(name); it != plan.existing.end()) {
      image_id = it->second;
      // New features renumber the keypoints its matches refer to.
      for (const image_t other : all_ids) {
        if (other == image_id) continue;
        db.DeletePair(image_id, other);
        record.DeletePairSettings(image_id, other);
      }
      // A photo replaced by one of another size: its camera's size and prior follow.
      const std::optional<DbImage> image = db.ReadImage(image_id);
      if (const std::optional<DbCamera> camera =
              image ? db.ReadCamera(image->camera_id) : std::nullopt;
          camera && (camera->width != item.camera.width || camera->height != item.camera.height)) {
        DbCamera resized = item.camera;
        resized.camera_id = camera->camera_id;
        db.UpdateCamera(resized);
      }
    } else {
      DbImage image;
      image.name = name;
      image.camera_id = db.WriteCamera(item.camera);
      image_id = db.WriteImage(image);
      image.image_id = image_id;
      added.push_back(image);
    }
    db.WriteKeypoints(image_id, item.features.keypoints);
    db.WriteDescriptors(image_id, item.features.descriptors);
    record.WriteImageSettings(image_id, settings);
    record.WriteImageFile(image_id, item.fingerprint);
    transaction.Commit();
    ++summary.num_extracted;
    summary.num_features += count;
    progress.Tick(1, name);
  };

  // A pipeline: images are extracted in parallel and written by one writer in name order
  // (deterministic ids), with a bounded number in flight to bound memory.
  const int threads = options.threads > 0 ? options.threads : tbb::task_arena::automatic;
  tbb::task_arena arena(threads);
  const ScopedMatBufferPool scale_space_buffers;
  const size_t tokens =
      PhotosInFlight(static_cast<size_t>(arena.max_concurrency()), photo_bytes, budget);
  if (tokens < static_cast<size_t>(arena.max_concurrency()))
    info("extract: {} photo(s) at a time: a scale space takes about {:.1f} GB, {:.1f} GB allowed",
         tokens, photo_bytes / 1e9, budget / 1e9);
  try {
    arena.execute([&] {
      size_t next = 0;
      tbb::parallel_pipeline(
          tokens,
          tbb::make_filter<void, size_t>(tbb::filter_mode::serial_in_order,
                                         [&](tbb::flow_control& control) -> size_t {
                                           if (next == todo.size()) {
                                             control.stop();
                                             return 0;
                                           }
                                           return todo[next++];
                                         }) &
              tbb::make_filter<size_t, std::shared_ptr<Extracted>>(
                  tbb::filter_mode::parallel,
                  [&](size_t index) { return std::make_shared<Extracted>(extract(index)); }) &
              tbb::make_filter<std::shared_ptr<Extracted>, void>(
                  tbb::filter_mode::serial_in_order,
                  [&](const std::shared_ptr<Extracted>& item) { write(*item); }));
    });
  } catch (...) {
    if (undo_on_failure) RemoveImages(db, added);
    throw;
  }
  progress.Finish();
  WarnOfCopies(db, record, input);
}

}  // namespace

void ExtractOptions::Check() const {
  sift.Check();
  keyframes.Check();
  CheckAtLeast("min_image_size", min_image_size, 1);
  CheckNonNegative("min_features", min_features);
  CheckNonNegative("--threads", threads);
  // A petabyte: any machine's memory, and MB that still count in bytes without overflow.
  CheckInRange("--memory-mb", memory_mb, size_t{0}, size_t{1} << 30);
}

ExtractSummary RunExtraction(const ExtractOptions& options, OptionsCheck check) {
  if (check == OptionsCheck::kByStage) options.Check();
  Timer timer;
  if (options.workspace.empty()) Fail("no workspace given");
  ExtractSummary summary;
  const InputImages input = ListInput(options, summary);
  summary.image_dir = input.dir;
  summary.num_images = input.names.size();
  const size_t n = input.names.size();

  // Find one usable image before touching the workspace, so that a folder of unreadable files
  // fails without creating or modifying it. The decoded image is reused below.
  std::vector<bool> unusable(n, false);
  std::optional<Photo> first_image;
  size_t first_index = n;
  for (size_t i = 0; i < n && !first_image; ++i) {
    first_image = LoadUsableImage(input.dir / input.names[i], options.min_image_size);
    if (first_image) {
      first_index = i;
    } else {
      unusable[i] = true;
      ++summary.num_unusable;
    }
  }
  if (!first_image) Fail("no readable image in {}", input.dir.string());

  if (!options.workspace.parent_path().empty()) CreateFolder(options.workspace.parent_path());
  std::error_code ec;
  const bool created = !fs::exists(options.workspace, ec);
  // A new workspace is created empty (SQLite takes an empty file for a new database) so that it
  // can be locked before it is written; a failure below removes it as any new workspace.
  if (created) std::ofstream(options.workspace, std::ios::binary | std::ios::app);
  const PathLock lock(options.workspace);
  try {
    Database db(options.workspace);
    WriteFeatures(db, options, input, first_index, std::move(first_image), unusable, summary,
                  /*undo_on_failure=*/!created);
    // A new workspace whose images have no feature at all cannot be matched: say so here, not
    // two stages later as "no initial pair".
    if (created && summary.num_features == 0)
      Fail("no feature in any of the {} images of {} (blank or textureless photos?)",
           summary.num_extracted, input.dir.string());
  } catch (...) {
    // A failed run leaves no workspace it made (the images it added to an existing one are
    // removed by WriteFeatures): a half-filled one would be mapped as if it were complete.
    if (created) RemoveWorkspace(options.workspace);
    throw;
  }
  summary.seconds = timer.Seconds();
  info(
      "extracted {} images ({} features, {:.0f} per image) in {:.1f} s; {} skipped as "
      "unusable",
      summary.num_extracted, summary.num_features,
      summary.num_extracted ? static_cast<double>(summary.num_features) / summary.num_extracted
                            : 0.0,
      summary.seconds, summary.num_unusable);
  return summary;
}

}  // namespace varsfm
