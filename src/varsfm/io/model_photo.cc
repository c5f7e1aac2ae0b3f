#include "varsfm/io/model_photo.h"

#include "varsfm/image/image_file.h"
#include "varsfm/util/error.h"

namespace varsfm {

cv::Mat ReadModelPhoto(const Reconstruction& reconstruction, image_t image_id,
                       const std::filesystem::path& image_dir) {
  const std::filesystem::path file = image_dir / reconstruction.image(image_id).name;
  cv::Mat pixels = ReadImagePixels(file, ColorMode::kColor);  // EXIF orientation applied
  const Camera& camera = reconstruction.CameraOf(image_id);
  if (pixels.cols != camera.width || pixels.rows != camera.height)
    Fail("image {} is {}x{} but its camera is {}x{}", file.string(), pixels.cols, pixels.rows,
         camera.width, camera.height);
  return pixels;
}

}  // namespace varsfm
