#include "varsfm/pipeline/render.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "varsfm/image/image_file.h"
#include "varsfm/io/colmap_model.h"
#include "varsfm/io/model_photo.h"
#include "varsfm/io/obj_io.h"
#include "varsfm/scene/holdout.h"
#include "varsfm/texture/model_texture.h"
#include "varsfm/texture/render.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"
#include "varsfm/util/new_folder.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/timer.h"

namespace varsfm {

namespace fs = std::filesystem;

fs::path TexturedObjPath(const fs::path& file_or_dir) {
  const fs::path obj = fs::is_directory(file_or_dir) ? file_or_dir / "model.obj" : file_or_dir;
  if (!fs::is_regular_file(obj)) Fail("{}: textured model does not exist", obj.string());
  return obj;
}

namespace {

RenderEvaluationMeans Means(const std::vector<RenderEvaluationRow>& rows, bool held_out) {
  RenderEvaluationMeans means;
  size_t scored = 0;
  for (const RenderEvaluationRow& row : rows) {
    if (row.held_out != held_out) continue;
    ++means.num_images;
    means.coverage += row.coverage;
    if (row.coverage > 0 && std::isfinite(row.psnr_db)) {
      means.psnr_db += row.psnr_db;
      means.psnr_exposure_db += row.psnr_exposure_db;
      means.ssim += row.ssim;
      ++scored;
    }
  }
  if (means.num_images) means.coverage /= means.num_images;
  if (scored) {
    means.psnr_db /= scored;
    means.psnr_exposure_db /= scored;
    means.ssim /= scored;
  }
  return means;
}

nlohmann::json ToJson(const RenderEvaluationMeans& means) {
  return {{"images", means.num_images},
          {"mean_psnr_db", means.psnr_db},
          {"mean_psnr_exposure_db", means.psnr_exposure_db},
          {"mean_ssim", means.ssim},
          {"mean_coverage", means.coverage}};
}

void WriteRenderedImage(const fs::path& file, const cv::Mat& image) {
  if (file.has_parent_path()) CreateFolder(file.parent_path());
  WriteImage(file, image);
}

// The registered image called `name`; an unknown name fails with a few of the names there are
// (a typo, or the name of a photo the model did not register).
image_t RegisteredImageNamed(const Reconstruction& rec, const std::string& name,
                             const fs::path& sparse) {
  const std::vector<image_t> ids = rec.RegisteredImageIds();
  for (const image_t id : ids)
    if (rec.image(id).name == name) return id;
  constexpr size_t kNamesShown = 4;
  std::vector<std::string> names;
  for (size_t i = 0; i < std::min(ids.size(), kNamesShown); ++i)
    names.push_back(rec.image(ids[i]).name);
  Fail("{}: no registered image named {} (it has {}: {}{})", sparse.string(), name, ids.size(),
       fmt::join(names, ", "), ids.size() > kNamesShown ? ", ..." : "");
}

}  // namespace

void RenderOptions::Check() const {
  if (camera.empty()) FailOption("--camera", "an image name of the sparse model", "''");
  if (output.empty()) FailOption("--output", "an image file", "''");
}

void RunRender(const RenderOptions& options) {
  options.Check();
  const fs::path sparse = options.sparse.empty() ? options.model / "sparse" : options.sparse;
  const fs::path textured =
      options.textured.empty() ? options.model / "textured" : options.textured;
  if (!fs::is_directory(sparse)) Fail("{}: sparse model folder does not exist", sparse.string());
  const Reconstruction rec = ReadColmapModel(sparse);
  const image_t id = RegisteredImageNamed(rec, options.camera, sparse);
  const TexturedMesh mesh = ReadTexturedObj(TexturedObjPath(textured));
  const Rendering r = RenderTexturedMesh(mesh, rec.CameraOf(id), rec.image(id).cam_from_world);
  if (options.panel_image_dir.empty()) {
    WriteRenderedImage(options.output, r.image);
  } else {
    const cv::Mat photo = ReadModelPhoto(rec, id, options.panel_image_dir);
    const cv::Mat shaded =
        RenderShadedMesh(mesh.vertices, mesh.faces, rec.CameraOf(id), rec.image(id).cam_from_world);
    cv::Mat panel;
    cv::hconcat(std::vector<cv::Mat>{photo, r.image, shaded}, panel);
    WriteRenderedImage(options.output, panel);
  }
  if (options.write_mask) {
    fs::path mask = options.output;
    mask.replace_filename(options.output.stem().string() + "_mask.png");
    WriteRenderedImage(mask, r.mask);
  }
  info("render: {} ({:.0f} % covered) -> {}", options.camera,
       100.0 * cv::countNonZero(r.mask) / r.mask.total(), options.output.string());
}

RenderEvaluationReport EvaluateRenders(const RenderEvaluationOptions& options) {
  Timer timer;
  if (!fs::is_directory(options.sparse))
    Fail("{}: model folder does not exist", options.sparse.string());
  if (!fs::is_directory(options.image_dir))
    Fail("{}: image folder does not exist", options.image_dir.string());
  const TexturedMesh mesh = ReadTexturedObj(TexturedObjPath(options.textured));
  const Reconstruction rec = ReadColmapModel(options.sparse);
  if (rec.NumRegisteredImages() == 0)
    Fail("{}: model has no registered images", options.sparse.string());
  RenderEvaluationReport report;
  size_t scored = 0;
  const std::vector<image_t> held_out = HeldOutImageIds(rec, options.holdout);
  for (const image_t id : rec.RegisteredImageIds()) {
    const Image& image = rec.image(id);
    const cv::Mat photo = ReadModelPhoto(rec, id, options.image_dir);
    const Rendering r = RenderTexturedMesh(mesh, rec.CameraOf(id), image.cam_from_world);
    const PhotometricScore s = ComparePhotometric(r, photo);
    const bool is_held_out = std::find(held_out.begin(), held_out.end(), id) != held_out.end();
    report.images.push_back(
        {image.name, s.psnr_db, s.psnr_exposure_db, s.ssim, s.coverage, is_held_out});
    if (!options.render_dir.empty())
      WriteRenderedImage(options.render_dir / (fs::path(image.name).stem().string() + ".png"),
                         r.image);
    report.mean_coverage += s.coverage;
    if (s.covered_pixels > 0 && std::isfinite(s.psnr_db)) {
      report.mean_psnr_db += s.psnr_db;
      ++scored;
    }
  }
  report.mean_coverage /= report.images.size();
  if (scored) report.mean_psnr_db /= scored;
  report.held_out = Means(report.images, true);
  report.source = Means(report.images, false);
  report.seconds = timer.Seconds();
  return report;
}

std::string FormatRenderReport(const RenderEvaluationReport& report) {
  std::string out = "Rendering of the textured model vs. photo (pixels the mesh covers)\n";
  out += fmt::format("  {:<32} {:>9} {:>10} {:>7} {:>9}\n", "image", "PSNR dB", "exposed dB",
                     "SSIM", "covered");
  for (const RenderEvaluationRow& row : report.images)
    out += fmt::format("  {:<32} {:>9.2f} {:>10.2f} {:>7.3f} {:>8.1f}%{}\n", row.name, row.psnr_db,
                       row.psnr_exposure_db, row.ssim, 100 * row.coverage,
                       row.held_out ? "  held out" : "");
  const auto line = [&](const std::string& label, const RenderEvaluationMeans& m) {
    out += fmt::format("  {:<32} {:>9.2f} {:>10.2f} {:>7.3f} {:>8.1f}%\n", label, m.psnr_db,
                       m.psnr_exposure_db, m.ssim, 100 * m.coverage);
  };
  if (report.held_out.num_images) {
    line(fmt::format("mean, {} held-out views", report.held_out.num_images), report.held_out);
    line(fmt::format("mean, {} source views", report.source.num_images), report.source);
  } else {
    line("mean", report.source);
  }
  out += "  (exposed: PSNR after a least-squares gain per colour channel, each photo's exposure)\n";
  return out;
}

nlohmann::json ToJson(const RenderEvaluationReport& report) {
  nlohmann::json j;
  j["mean_psnr_db"] = report.mean_psnr_db;
  j["mean_coverage"] = report.mean_coverage;
  j["held_out"] = ToJson(report.held_out);
  j["source"] = ToJson(report.source);
  j["seconds"] = report.seconds;
  j["images"] = nlohmann::json::array();
  for (const RenderEvaluationRow& row : report.images) {
    // JSON has no infinity: an exact match is reported as null.
    j["images"].push_back(
        {{"name", row.name},
         {"psnr_db", std::isfinite(row.psnr_db) ? nlohmann::json(row.psnr_db) : nlohmann::json()},
         {"psnr_exposure_db", std::isfinite(row.psnr_exposure_db)
                                  ? nlohmann::json(row.psnr_exposure_db)
                                  : nlohmann::json()},
         {"ssim", row.ssim},
         {"coverage", row.coverage},
         {"held_out", row.held_out}});
  }
  return j;
}

}  // namespace varsfm
