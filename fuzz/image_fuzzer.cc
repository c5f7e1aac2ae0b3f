// Image decoding as feature extraction does it (image/image_file.cc: JPEG completeness check,
// TurboJPEG, libpng, EXIF orientation; image/exif.cc: the focal-length prior). Other formats go
// to OpenCV through the I/O plug-in and are OpenCV's to fuzz, so inputs that are neither JPEG nor
// PNG are skipped. The last byte's parity picks grey or colour decoding.
#include "fuzz_support.h"
#include "varsfm/image/exif.h"
#include "varsfm/image/image_file.h"
#include "varsfm/image/jpeg_check.h"
#include "varsfm/image/jpeg_codec.h"
#include "varsfm/image/png_codec.h"
#include "varsfm/util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (!varsfm::LooksLikeJpeg(data, size) && !varsfm::LooksLikePng(data, size)) return 0;
  // As libjpeg-turbo's own fuzzers do, big JPEGs are skipped: a few bytes of progressive data
  // can declare up to kMaxImagePixels, and decoding that many takes seconds per execution. The
  // reader's own limit is tested in tests/image.
  if (int w = 0, h = 0; varsfm::JpegDimensions(data, size, &w, &h) && int64_t{w} * h > (1 << 20))
    return 0;
  const std::vector<uint8_t> bytes(data, data + size);
  const auto mode = data[size - 1] % 2 ? varsfm::ColorMode::kColor : varsfm::ColorMode::kGray;
  try {
    const cv::Mat pixels = varsfm::DecodeImage("input", bytes, mode);
    varsfm::ExifFocalLengthPixels(data, size, pixels.cols, pixels.rows);
  } catch (const varsfm::Error&) {
  }
  return 0;
}
