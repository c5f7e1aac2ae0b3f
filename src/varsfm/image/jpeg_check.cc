#include "varsfm/image/jpeg_check.h"

#include <cstring>

namespace varsfm {
namespace {

constexpr uint8_t kSoi = 0xD8, kEoi = 0xD9, kSos = 0xDA, kTem = 0x01;

bool IsRestart(uint8_t marker) { return marker >= 0xD0 && marker <= 0xD7; }

// Index of the first marker after entropy-coded data starting at `i`: 0xFF followed by a byte
// other than 0x00 (stuffing) or a restart marker, which both belong to the scan. Returns
// `size` if the data ends first.
size_t SkipEntropyCodedData(const uint8_t* data, size_t size, size_t i) {
  while (i + 1 < size) {
    const void* ff = std::memchr(data + i, 0xFF, size - i - 1);
    if (ff == nullptr) return size;
    i = static_cast<const uint8_t*>(ff) - data;
    const uint8_t next = data[i + 1];
    if (next != 0x00 && !IsRestart(next)) return i;
    i += 2;
  }
  return size;
}

}  // namespace

bool LooksLikeJpeg(const uint8_t* data, size_t size) {
  return size >= 3 && data[0] == 0xFF && data[1] == kSoi && data[2] == 0xFF;
}

bool IsCompleteJpeg(const uint8_t* data, size_t size) {
  if (!LooksLikeJpeg(data, size)) return false;
  size_t i = 2;
  while (i + 1 < size) {
    if (data[i] != 0xFF) return false;  // a marker must start here
    const uint8_t marker = data[i + 1];
    if (marker == 0xFF) {  // fill byte before a marker
      ++i;
      continue;
    }
    i += 2;
    if (marker == kEoi) return true;
    if (marker == kTem || IsRestart(marker)) continue;  // markers without a length
    if (i + 2 > size) return false;
    const size_t length = (size_t{data[i]} << 8) | data[i + 1];  // includes its own 2 bytes
    if (length < 2 || i + length > size) return false;
    i += length;
    if (marker == kSos) {
      i = SkipEntropyCodedData(data, size, i);
      if (i >= size) return false;  // the scan runs to the end of the data: truncated
    }
  }
  return false;
}

}  // namespace varsfm
