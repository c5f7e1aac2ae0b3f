#include "varsfm/image/image_io.h"

#include "varsfm/image/exif.h"

namespace varsfm {

Photo ReadPhoto(const std::filesystem::path& path, ColorMode mode) {
  // The bytes are read once and shared by the decoder and the EXIF parser.
  const std::vector<uint8_t> bytes = ReadImageFile(path);
  Photo image;
  image.pixels = DecodeImage(path, bytes, mode);
  image.exif_focal_px =
      ExifFocalLengthPixels(bytes.data(), bytes.size(), image.width(), image.height());
  return image;
}

}  // namespace varsfm
