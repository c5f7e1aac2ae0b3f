// The EXIF tags varsfm reads (image/exif.cc, on libexif): orientation and focal-length prior,
// from raw EXIF data ("Exif\0\0" + TIFF structure), as a JPEG's APP1 segment or a PNG's eXIf
// chunk hands it over. The image size comes from the first bytes so the resize scaling is reached.
#include <algorithm>

#include "fuzz_support.h"
#include "varsfm/image/exif.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  int width = 4000, height = 3000;
  if (size >= 2) {
    width = 1 + data[0] * 40;
    height = 1 + data[1] * 40;
  }
  const size_t skip = std::min<size_t>(size, 2);
  varsfm::ExifOrientation(data + skip, size - skip);
  varsfm::ExifFocalLengthPixels(data + skip, size - skip, width, height);
  return 0;
}
