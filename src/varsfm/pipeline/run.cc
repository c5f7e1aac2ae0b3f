#include "varsfm/pipeline/run.h"

#include <fstream>
#include <string>
#include <vector>

#include "varsfm/image/image_list.h"
#include "varsfm/image/video_keyframes.h"
#include "varsfm/io/database.h"
#include "varsfm/pipeline/output_folder.h"
#include "varsfm/pipeline/video_frames.h"
#include "varsfm/scene/holdout.h"
#include "varsfm/util/atomic_file.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"
#include "varsfm/util/path_lock.h"
#include "varsfm/util/timer.h"

namespace varsfm {

void RunOptions::Check() const {
  extract.Check();
  match.Check();
  map.Check();
  dense.Check();
  surface.Check();
  refinement.Check();
  texture.Check();
  CheckHoldout(holdout);
  report.data.Check();  // the report's output is this run's, set by RunAll
}

namespace {

// `run` builds the model of its input, but matching and mapping take every image of the
// workspace: an output folder of another set of photos or another video (or of this folder
// before photos were taken out of it) would mix that set's images into this model, silently.
// Refused before anything is written, so that workspace stays as it is. A photo belongs to the
// input when the folder holds a file of its name (the extraction lists the folder itself, with
// its warnings); a video's images are the keyframes in its own folder (video_frames.h).
void CheckWorkspaceHoldsOnlyInput(const std::filesystem::path& workspace,
                                  const std::filesystem::path& input, bool video) {
  if (!std::filesystem::exists(workspace)) return;
  const std::string folder = video ? VideoFramesFolderName(workspace, input) + "/" : "";
  std::vector<std::string> others;
  for (const DbImage& image : Database(workspace).ReadAllImages())
    if (video ? !image.name.starts_with(folder)
              : !std::filesystem::is_regular_file(input / image.name))
      others.push_back(image.name);
  if (others.empty()) return;
  Fail(
      "{} holds {} image(s) that are not {} {} (e.g. {}): it was made from other photos; give a "
      "new output folder, or empty this one to start afresh",
      workspace.string(), others.size(), video ? "keyframes of" : "in", input.string(),
      others.front());
}

// The stages that make the sparse model: extract, match, map. Returns the folder the photos
// were read from (a video's keyframes: their folder).
std::filesystem::path RunSparseStages(const RunOptions& options, const bool video,
                                      RunSummary* result, MatchStrategy* strategy) {
  const std::filesystem::path workspace = options.output / "workspace.db";
  Timer timer;
  ExtractOptions extract = options.extract;
  extract.workspace = workspace;
  extract.image_dir.clear();
  extract.video.clear();
  (video ? extract.video : extract.image_dir) = options.input;
  const ExtractSummary extracted = RunExtraction(extract, OptionsCheck::kDoneByCaller);
  result->seconds_extract = timer.Seconds();
  // One usable photo: said in the photo folder's terms, not by matching's count of images in a
  // workspace that the failed run then removes.
  const size_t usable = extracted.num_images - extracted.num_unusable;
  if (!video && usable < 2)
    Fail(
        "{} holds {} usable photo(s) ({} unusable): a model needs at least 2 overlapping photos "
        "of the scene taken from different positions",
        options.input.string(), usable, extracted.num_unusable);
  // A video whose frames barely differ gives one keyframe (a sharp one is kept whatever the
  // motion): said here in the video's terms rather than by matching's count of images. So does a
  // damaged or cut video whose decoding stops after a frame or two, for that reason.
  if (video && extracted.num_images < 2 &&
      DecodingStoppedShort(extracted.video_frames, extracted.video_announced))
    Fail(
        "video {} gave {} keyframe: decoding stopped at frame {} of the {} its container "
        "announces; the file is damaged or cut short",
        options.input.string(), extracted.num_images, extracted.video_frames,
        extracted.video_announced);
  if (video && extracted.num_images < 2)
    Fail(
        "video {} gave {} keyframe of {} frames ({} blurred): the camera hardly moves; film "
        "while moving around the scene",
        options.input.string(), extracted.num_images, extracted.video_frames,
        extracted.video_blurred);

  timer.Restart();
  MatchOptions match = options.match;
  match.workspace = workspace;
  match.strategy = options.matching;
  match.seed = options.map.mapper.seed;
  if (video && match.strategy == MatchStrategy::kAuto) match.strategy = MatchStrategy::kSequential;
  *strategy = RunMatching(match, OptionsCheck::kDoneByCaller).strategy;
  result->seconds_match = timer.Seconds();

  timer.Restart();
  MapOptions map = options.map;
  map.workspace = workspace;
  map.output = options.output;
  map.image_dir = extracted.image_dir;
  if (video) map.mapper.sequential_order = true;
  result->map = RunMapping(map, OptionsCheck::kDoneByCaller);
  result->seconds_map = timer.Seconds();
  return extracted.image_dir;
}

}  // namespace

RunSummary RunAll(const RunOptions& options, OptionsCheck check) {
  namespace fs = std::filesystem;
  if (check == OptionsCheck::kByStage) options.Check();
  if (!fs::exists(options.input)) Fail("input {} does not exist", options.input.string());
  const bool video = fs::is_regular_file(options.input);
  if (video && HasImageExtension(options.input))
    Fail("input {} is a photo: give the folder of the photos (or a video)", options.input.string());
  if (options.output.empty()) Fail("no output folder given");
  const auto runs = [&](RunStage stage) { return stage <= options.until; };
  if (fs::exists(options.output) && !fs::is_directory(options.output))
    Fail("output {} exists and is not a folder", options.output.string());
  const bool created_output = !fs::exists(options.output);
  OutputFolderLock output_lock(options.output);
  CheckOutputFolderIsOurs(options.output);
  if (!video) CheckOutputOutsideImages(options.output, options.input);
  CheckWorkspaceHoldsOnlyInput(options.output / "workspace.db", options.input, video);
  output_lock.CreateAndLock();

  RunSummary result;
  MatchStrategy strategy = options.matching;
  fs::path image_dir;
  try {
    image_dir = RunSparseStages(options, video, &result, &strategy);
  } catch (...) {
    // Nothing of value was made: a failed run leaves no folder behind it.
    std::error_code ec;
    if (created_output) fs::remove_all(options.output, ec);
    throw;
  }

  // Add the earlier stages' times to the summary written by the mapping stage.
  const fs::path summary_path = options.output / "summary.json";
  nlohmann::json summary = nlohmann::json::parse(std::ifstream(summary_path));
  summary["seconds"]["extract"] = result.seconds_extract;
  summary["seconds"]["match"] = result.seconds_match;
  summary["seconds"]["map"] = result.seconds_map;
  summary["matching_strategy"] = std::string(NameOf(kMatchStrategyNames, strategy));
  WriteJsonAtomically(summary_path, summary);

  // Unconnected images give further models (sparse/1, ...); the later stages use model 0.
  const size_t num_models = 1 + result.map.more_models.size();
  info("run: wrote {}/sparse/{} (COLMAP text + binary), sparse.ply, bundle.out, summary.json",
       options.output.string(), num_models > 1 ? fmt::format("0 .. {}", num_models - 1) : "0");
  if (num_models > 1 && runs(RunStage::kDense)) {
    size_t others = 0;
    for (const MapperModel& model : result.map.more_models)
      others += model.reconstruction.NumRegisteredImages();
    warn(
        "run: {} models: the dense cloud, mesh and textured model are made from model 0 ({} "
        "images), not from the {} images of {} (densify, mesh and texture take --sparse "
        "{}/sparse/K for model K)",
        num_models, result.map.reconstruction.NumRegisteredImages(), others,
        num_models == 2 ? "model 1" : fmt::format("models 1 .. {}", num_models - 1),
        options.output.string());
  }

  // Dense cloud, surface and texture, each stage's time added to the summary as it ends.
  const auto add_seconds = [&](const char* stage, double seconds) {
    summary["seconds"][stage] = seconds;
    WriteJsonAtomically(summary_path, summary);
  };
  if (runs(RunStage::kDense)) {
    DensifyOptions densify;
    densify.sparse = options.output / "sparse" / "0";
    densify.image_dir = image_dir;
    densify.output = options.output;
    densify.dense = options.dense;
    densify.dense.mvs.seed = options.map.mapper.seed;
    densify.holdout = options.holdout;
    result.seconds_densify = RunDensify(densify, OptionsCheck::kDoneByCaller).seconds;
    add_seconds("densify", result.seconds_densify);
  }
  if (runs(RunStage::kMesh)) {
    MeshOptions mesh;
    mesh.input = options.output / "dense.ply";
    mesh.output = options.output;
    mesh.sparse = options.output / "sparse" / "0";
    mesh.holdout = options.holdout;
    mesh.surface = options.surface;
    mesh.refinement = options.refinement;
    mesh.image_dir = image_dir;
    const MeshSummary meshed = RunMesh(mesh, OptionsCheck::kDoneByCaller);
    result.seconds_mesh = meshed.seconds;
    summary["mesh"] = MeshSummaryJson(meshed);
    add_seconds("mesh", result.seconds_mesh);
  }
  if (runs(RunStage::kTexture)) {
    TextureOptions texture;
    texture.mesh = options.output / "mesh.ply";
    texture.sparse = options.output / "sparse" / "0";
    texture.image_dir = image_dir;
    texture.output = options.output;
    texture.texture = options.texture;
    texture.holdout = options.holdout;
    const TextureSummary textured = RunTexture(texture, OptionsCheck::kDoneByCaller);
    result.seconds_texture = textured.seconds;
    summary["texture"] = {{"faces", textured.stats.num_faces},
                          {"textured_faces", textured.stats.num_textured_faces},
                          {"mean_coverage", textured.stats.mean_coverage}};
    add_seconds("texture", result.seconds_texture);
    if (options.holdout > 0) {
      RenderEvaluationOptions renders;
      renders.sparse = texture.sparse;
      renders.textured = options.output / "textured";
      renders.image_dir = image_dir;
      renders.holdout = options.holdout;
      result.renders = EvaluateRenders(renders);
      const RenderEvaluationMeans& h = result.renders.held_out;
      const RenderEvaluationMeans& s = result.renders.source;
      info(
          "run: {} held-out views: PSNR {:.2f} dB ({:.2f} dB after each photo's exposure), SSIM "
          "{:.3f} over {:.1f} % of the pixels (source views: {:.2f} dB, SSIM {:.3f}, {:.1f} %)",
          h.num_images, h.psnr_db, h.psnr_exposure_db, h.ssim, 100 * h.coverage, s.psnr_db, s.ssim,
          100 * s.coverage);
      summary["renders"] = ToJson(result.renders);
      add_seconds("render_evaluation", result.renders.seconds);
    }
  }
  // The report only shows what the stages made: a failure to write it is a warning, not a
  // failed run.
  ReportOptions report = options.report;
  report.output = options.output;
  try {
    result.report = RunReport(report, OptionsCheck::kDoneByCaller).file;
  } catch (const std::exception& e) {
    warn("run: no report: {}", e.what());
  }
  const Reconstruction& model = result.map.reconstruction;
  info("run: {}/{} images registered{}, {} points, RMS {:.3f} px, {:.1f} s; report: {}",
       model.NumRegisteredImages(), result.map.num_images,
       num_models > 1 ? fmt::format(" in model 0 of {}", num_models) : "", model.points3D().size(),
       model.RmsReprojectionError(),
       result.seconds_extract + result.seconds_match + result.seconds_map + result.seconds_densify +
           result.seconds_mesh + result.seconds_texture,
       result.report.empty() ? "none" : result.report.string());
  return result;
}

}  // namespace varsfm
