#include "varsfm/export/gaussian_splatting.h"

#include <algorithm>
#include <vector>

#include <tbb/parallel_for.h>

#include "varsfm/camera/colmap_models.h"
#include "varsfm/export/exported_images.h"
#include "varsfm/export/undistortion.h"
#include "varsfm/image/image_file.h"
#include "varsfm/io/colmap_model.h"
#include "varsfm/util/error.h"
#include "varsfm/util/new_folder.h"

namespace varsfm {

Camera ExportedPinholeCamera(const Camera& camera, PrincipalPointPlacement placement) {
  const Camera kept = UndistortedPinholeCamera(camera, PrincipalPointPlacement::kKept);
  if (placement == PrincipalPointPlacement::kKept) return kept;
  try {
    const Camera centred = UndistortedPinholeCamera(camera, PrincipalPointPlacement::kCentred);
    if (static_cast<double>(centred.width) * centred.height >=
        kMinCentredArea * static_cast<double>(kept.width) * kept.height)
      return centred;
  } catch (const Error&) {
    // The principal point lies outside the photo or on its border: it stays where it is.
  }
  return kept;
}

Reconstruction UndistortReconstruction(const Reconstruction& reconstruction,
                                       PrincipalPointPlacement placement) {
  Reconstruction undistorted = reconstruction;
  for (const auto& [camera_id, camera] : reconstruction.cameras()) {
    undistorted.camera(camera_id) = ExportedPinholeCamera(camera, placement);
  }
  for (const image_t image_id : reconstruction.RegisteredImageIds()) {
    const Camera& camera = reconstruction.CameraOf(image_id);
    const Camera& pinhole = undistorted.CameraOf(image_id);
    for (Point2D& point : undistorted.image(image_id).points2D) {
      point.xy = UndistortPixel(camera, pinhole, point.xy);
    }
  }
  return undistorted;
}

GaussianSplattingExportSummary ExportGaussianSplatting(const Reconstruction& reconstruction,
                                                       const std::filesystem::path& image_dir,
                                                       const std::filesystem::path& output,
                                                       PrincipalPointPlacement placement) {
  const std::vector<image_t> image_ids = ExportedImageIds(reconstruction, image_dir);
  Reconstruction undistorted = UndistortReconstruction(reconstruction, placement);
  for (const image_t id : image_ids)
    undistorted.image(id).name = ExportedPhotoName(reconstruction.image(id).name);
  WriteNewFolder(output, [&](const std::filesystem::path& dir) {
    for (const image_t id : image_ids) {
      std::filesystem::create_directories(
          (dir / "images" / undistorted.image(id).name).parent_path());
    }
    // Images are independent; the first error (a photo that cannot be read) is rethrown.
    std::vector<std::string> errors(image_ids.size());
    tbb::parallel_for(size_t{0}, image_ids.size(), [&](size_t i) {
      try {
        const Image& image = reconstruction.image(image_ids[i]);
        const cv::Mat photo = ReadImagePixels(image_dir / image.name, ColorMode::kColor);
        const cv::Mat pixels = UndistortImage(photo, reconstruction.CameraOf(image.image_id),
                                              undistorted.CameraOf(image.image_id));
        WriteImage(dir / "images" / undistorted.image(image.image_id).name, pixels);
      } catch (const Error& e) {
        errors[i] = fmt::format("{}: {}", reconstruction.image(image_ids[i]).name, e.what());
      }
    });
    for (const std::string& error : errors) {
      if (!error.empty()) throw Error(error);
    }
    ColmapWriteOptions colmap;
    colmap.binary = true;
    colmap.force_model_id = kColmapPinhole;
    WriteColmapModel(undistorted, dir / "sparse" / "0", colmap);
  });
  GaussianSplattingExportSummary summary;
  summary.num_images = image_ids.size();
  summary.num_points = reconstruction.points3D().size();
  for (const image_t id : image_ids) {
    const Camera& c = undistorted.CameraOf(id);
    if (c.PrincipalPointOffset().isZero(0.0) && placement == PrincipalPointPlacement::kCentred)
      ++summary.num_centred;
    if (c.PrincipalPointOffset().norm() > kOffCentrePrincipalPoint * std::max(c.width, c.height))
      ++summary.num_off_centre;
  }
  return summary;
}

}  // namespace varsfm
