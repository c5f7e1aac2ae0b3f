#include "varsfm/export/exported_images.h"

#include "varsfm/image/heif_codec.h"
#include "varsfm/image/raw_codec.h"
#include "varsfm/util/error.h"

namespace varsfm {

std::vector<image_t> ExportedImageIds(const Reconstruction& reconstruction,
                                      const std::filesystem::path& image_dir) {
  const std::vector<image_t> image_ids = reconstruction.RegisteredImageIds();
  if (image_ids.empty()) Fail("the model has no registered image to export");
  for (const image_t id : image_ids) {
    const std::filesystem::path photo = image_dir / reconstruction.image(id).name;
    if (!std::filesystem::is_regular_file(photo)) Fail("{}: no such photo", photo.string());
  }
  return image_ids;
}

std::string ExportedPhotoName(const std::string& name) {
  return IsHeifPhotoName(name) || IsRawPhotoName(name) ? name + ".jpg" : name;
}

}  // namespace varsfm
