#include "varsfm/report/deflate.h"

#include <zlib.h>

#include "varsfm/util/error.h"

namespace varsfm {

std::vector<uint8_t> Deflate(const std::vector<uint8_t>& bytes) {
  uLongf size = compressBound(bytes.size());
  std::vector<uint8_t> out(size);
  // Level 6, zlib's default: level 9 gains nothing on quantised geometry and JPEG.
  if (compress2(out.data(), &size, bytes.data(), bytes.size(), 6) != Z_OK)
    Fail("report: cannot compress the model");
  out.resize(size);
  return out;
}

}  // namespace varsfm
