#include "varsfm/pipeline/export.h"

#include <fstream>

#include <nlohmann/json.hpp>

#include "varsfm/export/gaussian_splatting.h"
#include "varsfm/export/nerfstudio.h"
#include "varsfm/io/colmap_model.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/timer.h"

namespace varsfm {
namespace {

// A run's output folder (its sparse/, model 0), or a model folder or a folder of numbered models.
std::filesystem::path FindModelFolder(const std::filesystem::path& path) {
  const std::filesystem::path dir = ResolveColmapModelFolder(
      std::filesystem::is_directory(path / "sparse") ? path / "sparse" : path);
  if (!std::filesystem::exists(dir / "cameras.bin") &&
      !std::filesystem::exists(dir / "cameras.txt")) {
    Fail("--model {}: no COLMAP model there (cameras.bin or cameras.txt), nor in its sparse/0",
         path.string());
  }
  return dir;
}

// The photos: as given, or where the run that made the model read them (OUT/summary.json).
std::filesystem::path FindImageFolder(const ExportOptions& options) {
  if (!options.image_dir.empty()) return options.image_dir;
  const std::filesystem::path summary_file = options.model / "summary.json";
  if (std::filesystem::is_regular_file(summary_file)) {
    const nlohmann::json summary =
        nlohmann::json::parse(std::ifstream(summary_file), nullptr, /*allow_exceptions=*/false);
    if (summary.is_object() && summary.contains("image_dir") && summary["image_dir"].is_string())
      return summary["image_dir"].get<std::string>();
  }
  Fail("--images: not given, and {} does not say where the photos are", summary_file.string());
}

}  // namespace

void ExportOptions::Check() const {
  if (model.empty()) FailOption("model", "a model folder", "''");
  if (!std::filesystem::exists(model)) Fail("--model {}: no such folder", model.string());
  if (!image_dir.empty() && !std::filesystem::is_directory(image_dir)) {
    Fail("--images {}: no such folder", image_dir.string());
  }
  if (output.empty()) FailOption("output", "a folder to create", "''");
  if (format != ExportFormat::kGaussianSplatting && !centre_principal_point)
    throw OptionError(
        "--keep-principal-point: only for --format 3dgs (nerfstudio keeps every photo whole, "
        "with its cx, cy)");
  std::error_code ec;
  if (std::filesystem::exists(output, ec) &&
      (!std::filesystem::is_directory(output, ec) || !std::filesystem::is_empty(output, ec))) {
    Fail("--output {}: already exists and is not an empty folder", output.string());
  }
}

ExportSummary RunExport(const ExportOptions& options) {
  options.Check();
  Timer timer;
  const std::filesystem::path model_dir = FindModelFolder(options.model);
  const Reconstruction reconstruction = ReadColmapModel(model_dir);
  const std::filesystem::path image_dir = FindImageFolder(options);
  if (!std::filesystem::is_directory(image_dir)) {
    Fail("{}: the photos' folder does not exist (give --images)", image_dir.string());
  }
  ExportSummary summary;
  if (options.format == ExportFormat::kGaussianSplatting) {
    const GaussianSplattingExportSummary s =
        ExportGaussianSplatting(reconstruction, image_dir, options.output,
                                options.centre_principal_point ? PrincipalPointPlacement::kCentred
                                                               : PrincipalPointPlacement::kKept);
    summary.num_images = s.num_images;
    summary.num_points = s.num_points;
    if (options.centre_principal_point)
      info(
          "export: {} of {} photos cut around their principal point, which lies at their centre "
          "(3D Gaussian Splatting's loader assumes it there)",
          s.num_centred, s.num_images);
    if (s.num_off_centre > 0)
      warn(
          "export: {} of {} photos keep a principal point more than {:.0f} % of the image off its "
          "centre ({}): 3D Gaussian Splatting's reference loader ignores cx, cy and misplaces "
          "them; trainers that read cx, cy (gsplat, nerfstudio) do not",
          s.num_off_centre, s.num_images, 100 * kOffCentrePrincipalPoint,
          options.centre_principal_point
              ? fmt::format("cropped far off-centre: centred, less than {:.0f} % of the photo "
                            "would remain",
                            100 * kMinCentredArea)
              : "--keep-principal-point");
  } else {
    const NerfstudioExportSummary s = ExportNerfstudio(reconstruction, image_dir, options.output);
    summary.num_images = s.num_frames;
    summary.num_points = s.num_points;
  }
  summary.seconds = timer.Seconds();
  info("export: {} images, {} points from {} in {:.1f} s -> {}", summary.num_images,
       summary.num_points, model_dir.string(), summary.seconds, options.output.string());
  return summary;
}

}  // namespace varsfm
