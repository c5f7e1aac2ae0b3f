#include "varsfm/image/image_io.h"

#include "varsfm/image/exif.h"
#include "varsfm/image/heif_codec.h"
#include "varsfm/image/raw_codec.h"

namespace varsfm {

Photo ReadPhoto(const std::filesystem::path& path, ColorMode mode) {
  // The bytes are read once and shared by the decoder and the EXIF parser.
  const std::vector<uint8_t> bytes = ReadImageFile(path);
  Photo image;
  image.pixels = DecodeImage(path, bytes, mode);
  if (IsRawPhotoName(path)) {  // its EXIF as LibRaw parses it
    if (const auto f35 = RawFocalLength35mm(bytes.data(), bytes.size()))
      image.exif_focal_px = FocalPixelsFrom35mmEquivalent(*f35, image.width(), image.height());
    return image;
  }
  // A HEIF file keeps its EXIF in a metadata item, which libexif cannot find in the file.
  const std::vector<uint8_t> heif_exif = LooksLikeHeif(bytes.data(), bytes.size())
                                             ? HeifExif(bytes.data(), bytes.size())
                                             : std::vector<uint8_t>{};
  const std::vector<uint8_t>& exif = heif_exif.empty() ? bytes : heif_exif;
  image.exif_focal_px =
      ExifFocalLengthPixels(exif.data(), exif.size(), image.width(), image.height());
  return image;
}

}  // namespace varsfm
