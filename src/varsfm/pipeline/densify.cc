#include "varsfm/pipeline/densify.h"

#include <opencv2/imgcodecs.hpp>

#include "varsfm/io/colmap_model.h"
#include "varsfm/io/ply.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"
#include "varsfm/util/timer.h"

namespace varsfm {

DensifyCommandResult RunDensify(const DensifyCommandOptions& options) {
  Timer timer;
  if (!options.workspace.empty() && !std::filesystem::exists(options.workspace))
    Fail("workspace {} does not exist", options.workspace.string());
  if (!std::filesystem::is_directory(options.sparse))
    Fail("sparse model folder {} does not exist", options.sparse.string());
  if (!std::filesystem::is_directory(options.image_dir))
    Fail("image folder {} does not exist", options.image_dir.string());
  const Reconstruction rec = ReadColmapModel(options.sparse);
  if (rec.NumRegisteredImages() < 2)
    Fail("sparse model {} has {} registered images; densify needs at least 2",
         options.sparse.string(), rec.NumRegisteredImages());

  const auto load = [&](image_t id) {
    const Image& image = rec.image(id);
    const std::filesystem::path file = options.image_dir / image.name;
    cv::Mat pixels = cv::imread(file.string(), cv::IMREAD_COLOR);  // EXIF orientation applied
    if (pixels.empty()) Fail("cannot read image {}", file.string());
    const Camera& camera = rec.CameraOf(id);
    if (pixels.cols != camera.width || pixels.rows != camera.height)
      Fail("image {} is {}x{} but its camera is {}x{}", file.string(), pixels.cols, pixels.rows,
           camera.width, camera.height);
    return pixels;
  };
  DensifyCommandResult result;
  const PointCloud cloud = Densify(rec, load, options.dense, &result.stats);
  std::filesystem::create_directories(options.output);
  WritePly(options.output / "dense.ply", cloud);
  result.num_points = cloud.points.size();
  result.seconds = timer.Seconds();
  info("densify: wrote {} points to {} in {:.1f} s", result.num_points,
       (options.output / "dense.ply").string(), result.seconds);
  return result;
}

}  // namespace varsfm
