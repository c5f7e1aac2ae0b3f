#include "support/dng_writer.h"

#include <algorithm>
#include <cstring>

namespace varsfm::testing {
namespace {

enum Type : uint16_t {
  kByte = 1,
  kAscii = 2,
  kShort = 3,
  kLong = 4,
  kRational = 5,
  kSRational = 10
};

struct Entry {
  uint16_t tag;
  Type type;
  uint32_t count;
  std::vector<uint8_t> value;  // little-endian
};

template <typename T>
void Append(std::vector<uint8_t>* out, T v) {
  const size_t at = out->size();
  out->resize(at + sizeof(T));
  std::memcpy(out->data() + at, &v, sizeof(T));  // x86-64: little-endian
}

Entry Shorts(uint16_t tag, std::vector<uint16_t> values) {
  Entry e{tag, kShort, static_cast<uint32_t>(values.size()), {}};
  for (const uint16_t v : values) Append(&e.value, v);
  return e;
}
Entry Longs(uint16_t tag, std::vector<uint32_t> values) {
  Entry e{tag, kLong, static_cast<uint32_t>(values.size()), {}};
  for (const uint32_t v : values) Append(&e.value, v);
  return e;
}
Entry Bytes(uint16_t tag, std::vector<uint8_t> values) {
  return {tag, kByte, static_cast<uint32_t>(values.size()), values};
}
Entry Text(uint16_t tag, const char* text) {
  std::vector<uint8_t> v(text, text + std::strlen(text) + 1);
  return {tag, kAscii, static_cast<uint32_t>(v.size()), v};
}
Entry Rationals(uint16_t tag, Type type, std::vector<std::pair<int32_t, int32_t>> values) {
  Entry e{tag, type, static_cast<uint32_t>(values.size()), {}};
  for (const auto& [n, d] : values) Append(&e.value, n), Append(&e.value, d);
  return e;
}

// An IFD at `offset` with its values beyond 4 bytes after it: its bytes.
std::vector<uint8_t> Ifd(std::vector<Entry> entries, uint32_t offset) {
  std::sort(entries.begin(), entries.end(),
            [](const Entry& a, const Entry& b) { return a.tag < b.tag; });
  const uint32_t values_at = offset + 2 + 12 * static_cast<uint32_t>(entries.size()) + 4;
  std::vector<uint8_t> ifd, values;
  Append(&ifd, static_cast<uint16_t>(entries.size()));
  for (const Entry& e : entries) {
    Append(&ifd, e.tag), Append(&ifd, static_cast<uint16_t>(e.type)), Append(&ifd, e.count);
    if (e.value.size() <= 4) {
      std::vector<uint8_t> inline_value = e.value;
      inline_value.resize(4, 0);
      ifd.insert(ifd.end(), inline_value.begin(), inline_value.end());
    } else {
      Append(&ifd, values_at + static_cast<uint32_t>(values.size()));
      values.insert(values.end(), e.value.begin(), e.value.end());
      if (values.size() % 2) values.push_back(0);
    }
  }
  Append(&ifd, uint32_t{0});  // no next IFD
  ifd.insert(ifd.end(), values.begin(), values.end());
  return ifd;
}

}  // namespace

std::vector<uint8_t> EncodeDng(const cv::Mat& bgr, int orientation, int focal_35mm) {
  const int w = bgr.cols, h = bgr.rows;
  constexpr uint16_t kWhite = 4095;
  std::vector<uint8_t> mosaic;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int channel = (y % 2 == 0 && x % 2 == 0) ? 2 : (y % 2 == 1 && x % 2 == 1) ? 0 : 1;
      Append(&mosaic, static_cast<uint16_t>(bgr.at<cv::Vec3b>(y, x)[channel] * kWhite / 255));
    }
  // The EXIF IFD (when there is a focal length) right after the header, then IFD0, the mosaic.
  const std::vector<uint8_t> exif =
      focal_35mm > 0 ? Ifd({Shorts(41989, {static_cast<uint16_t>(focal_35mm)})}, 8)
                     : std::vector<uint8_t>{};
  const uint32_t ifd0_at = 8 + static_cast<uint32_t>(exif.size());
  std::vector<Entry> entries = {
      Longs(254, {0}),
      Longs(256, {static_cast<uint32_t>(w)}),
      Longs(257, {static_cast<uint32_t>(h)}),
      Shorts(258, {16}),
      Shorts(259, {1}),
      Shorts(262, {32803}),  // CFA
      Text(271, "varsfm"),
      Text(272, "test DNG"),
      Longs(273, {0}),  // the strip's offset, set below
      Shorts(274, {static_cast<uint16_t>(orientation)}),
      Shorts(277, {1}),
      Longs(278, {static_cast<uint32_t>(h)}),
      Longs(279, {static_cast<uint32_t>(mosaic.size())}),
      Shorts(284, {1}),
      Shorts(33421, {2, 2}),
      Bytes(33422, {0, 1, 1, 2}),  // RGGB
      Bytes(50706, {1, 4, 0, 0}),
      Text(50708, "varsfm test DNG"),
      Longs(50714, {0}),
      Longs(50717, {kWhite}),
      Rationals(50721, kSRational,
                {{1, 1}, {0, 1}, {0, 1}, {0, 1}, {1, 1}, {0, 1}, {0, 1}, {0, 1}, {1, 1}}),
      Rationals(50728, kRational, {{1, 1}, {1, 1}, {1, 1}}),
      Shorts(50778, {21}),  // D65
  };
  if (focal_35mm > 0) entries.push_back(Longs(34665, {8}));  // the EXIF IFD
  const uint32_t ifd0_size = static_cast<uint32_t>(Ifd(entries, ifd0_at).size());
  entries[8] = Longs(273, {ifd0_at + ifd0_size});
  std::vector<uint8_t> file = {'I', 'I', 42, 0};
  Append(&file, ifd0_at);
  file.insert(file.end(), exif.begin(), exif.end());
  const std::vector<uint8_t> ifd0 = Ifd(entries, ifd0_at);
  file.insert(file.end(), ifd0.begin(), ifd0.end());
  file.insert(file.end(), mosaic.begin(), mosaic.end());
  return file;
}

}  // namespace varsfm::testing
