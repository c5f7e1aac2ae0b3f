#pragma once
// `varsfm export`: a sparse model and its photos in the layout of the tool a user takes them to
// next — 3D Gaussian Splatting (undistorted images + PINHOLE COLMAP model) or nerfstudio
// (transforms.json with per-frame intrinsics).
#include <filesystem>
#include <string>

#include "varsfm/util/enum_names.h"

namespace varsfm {

enum class ExportFormat { kGaussianSplatting, kNerfstudio };

// The names `--format` takes.
inline constexpr EnumName<ExportFormat> kExportFormatNames[] = {
    {ExportFormat::kGaussianSplatting, "3dgs"}, {ExportFormat::kNerfstudio, "nerfstudio"}};
// Throws varsfm::Error naming the choices for a name that is none of them.
inline ExportFormat ParseExportFormat(const std::string& name) {
  return ValueOf(kExportFormatNames, name, "export format");
}

struct ExportOptions {
  ExportFormat format = ExportFormat::kGaussianSplatting;
  // A COLMAP model folder, or the output folder of `run` / `map` (its model 0 is exported).
  std::filesystem::path model;
  // The photos, by the model's image names; empty: where the run that made the model read them
  // (the "image_dir" of MODEL/summary.json).
  std::filesystem::path image_dir;
  std::filesystem::path output;  // created; must not exist or be empty
  // 3dgs: each photo cut around its principal point so that it lies at the image centre, as 3D
  // Gaussian Splatting's reference loader assumes (export/gaussian_splatting.h); false: kept
  // where it is, every pixel of the undistorted photo kept (COLMAP image_undistorter's layout,
  // for trainers that read cx, cy).
  bool centre_principal_point = true;

  // Throws OptionError (util/option_check.h) for no model or no output path, varsfm::Error (one
  // line naming the folder) for a model or image folder that does not exist or an output that
  // already holds files.
  void Check() const;
};

struct ExportSummary {
  size_t num_images = 0;
  size_t num_points = 0;
  double seconds = 0;
};

ExportSummary RunExport(const ExportOptions& options);

}  // namespace varsfm
