#pragma once
// `varsfm render` and `varsfm evaluate --render`: the textured model drawn from registered
// cameras (texture/render.h), to look at beside the photos and to score the whole chain by the
// photometric error between rendering and photo over the pixels the mesh covers.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace varsfm {

struct RenderOptions {
  std::filesystem::path model;     // OUT of `texture` (OUT/textured/model.obj, OUT/sparse)
  std::filesystem::path sparse;    // empty: OUT/sparse (its model 0)
  std::filesystem::path textured;  // OBJ file or its folder; empty: OUT/textured/model.obj
  std::string camera;              // image name in the sparse model
  std::filesystem::path output;    // image file (PNG), black where the mesh does not reach
  bool write_mask = false;         // also write the coverage mask beside it (NAME_mask.png)
  // With the photos' folder: the output is three panels side by side, photo | rendering | the
  // mesh shaded without texture, to look at a view (a held-out one above all) as a person would.
  std::filesystem::path panel_image_dir;

  // Throws OptionError (util/option_check.h) for an empty camera name or output; files are
  // checked when the stage runs.
  void Check() const;
};

// Throws varsfm::Error (one line) for a missing model, an unknown image name, or an unwritable
// output.
void RunRender(const RenderOptions& options);

struct RenderEvaluationOptions {
  std::filesystem::path sparse;      // COLMAP model folder (or its parent: model 0)
  std::filesystem::path textured;    // OBJ file or its folder
  std::filesystem::path image_dir;   // the photos
  std::filesystem::path render_dir;  // optional: renderings written here as NAME.png
  // The novel-view protocol (scene/holdout.h): every N-th registered image by name was kept out
  // of densification and texturing; those are reported apart (0: no held-out views).
  int holdout = 0;
};

struct RenderEvaluationRow {
  std::string name;
  double psnr_db = 0;
  double psnr_exposure_db = 0;  // after a gain per colour channel (texture/render.h)
  double ssim = 0;
  double coverage = 0;
  bool held_out = false;
};

// Means over a group of views; PSNR and SSIM over the views that cover at least one pixel.
struct RenderEvaluationMeans {
  size_t num_images = 0;
  double psnr_db = 0;
  double psnr_exposure_db = 0;
  double ssim = 0;
  double coverage = 0;
};

struct RenderEvaluationReport {
  std::vector<RenderEvaluationRow> images;  // every registered image, in id order
  double mean_psnr_db = 0;                  // over images that cover at least one pixel
  double mean_coverage = 0;
  RenderEvaluationMeans held_out;  // the held-out views (none without a holdout)
  RenderEvaluationMeans source;    // the views the model was made from
  double seconds = 0;
};

// Throws varsfm::Error (one line) for a missing model, textured model or photo.
RenderEvaluationReport EvaluateRenders(const RenderEvaluationOptions& options);
std::string FormatRenderReport(const RenderEvaluationReport& report);
nlohmann::json ToJson(const RenderEvaluationReport& report);

// The OBJ file of a textured model given as the file itself or a folder holding model.obj.
std::filesystem::path TexturedObjPath(const std::filesystem::path& file_or_dir);

}  // namespace varsfm
