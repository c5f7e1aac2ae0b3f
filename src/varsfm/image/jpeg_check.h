#pragma once
// A structural check of JPEG data. libjpeg decodes a truncated file without failing (it pads
// the missing rows with grey and only prints a warning), so OpenCV returns a half-grey image;
// walking the markers up to the end-of-image marker catches such files before decoding.
#include <cstddef>
#include <cstdint>

namespace varsfm {

// True when `data` starts like a JPEG (SOI marker).
bool LooksLikeJpeg(const uint8_t* data, size_t size);

// True when the JPEG segments are well-formed and the end-of-image marker is reached, false
// for truncated or corrupt marker structure. Entropy-coded data itself is not decoded.
bool IsCompleteJpeg(const uint8_t* data, size_t size);

}  // namespace varsfm
