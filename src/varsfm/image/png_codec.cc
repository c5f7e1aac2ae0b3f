#include "varsfm/image/png_codec.h"

#include <png.h>
#include <zlib.h>

#include <bit>
#include <cstdint>
#include <cstring>

namespace varsfm {
namespace {

constexpr uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

// libpng reports errors by longjmp; the setjmp in each helper keeps that inside this file. The
// helpers own no C++ objects, so a longjmp skips no destructor.
struct ReadState {
  const uint8_t* data;
  size_t size;
  size_t position;
};

void ReadFromMemory(png_structp png, png_bytep out, png_size_t length) {
  auto* state = static_cast<ReadState*>(png_get_io_ptr(png));
  if (length > state->size - state->position) png_error(png, "unexpected end of PNG data");
  std::memcpy(out, state->data + state->position, length);
  state->position += length;
}

void WriteToVector(png_structp png, png_bytep data, png_size_t length) {
  auto* out = static_cast<std::vector<uint8_t>*>(png_get_io_ptr(png));
  out->insert(out->end(), data, data + length);
}

void FlushNothing(png_structp) {}

// Errors return to the setjmp of the caller without printing (the caller throws one line
// naming the file); warnings (e.g. a known-incorrect sRGB profile) are not worth reporting.
[[noreturn]] void JumpOnError(png_structp png, png_const_charp) { png_longjmp(png, 1); }
void IgnoreWarning(png_structp, png_const_charp) {}

// Reads the header and sets up OpenCV's PngDecoder::readData transformations for an 8-bit
// 1- or 3-channel result; false on a libpng error.
bool ReadHeader(png_structp png, png_infop info, ColorMode mode, png_uint_32* width,
                png_uint_32* height) {
  if (setjmp(png_jmpbuf(png)) != 0) return false;
  png_read_info(png, info);
  int bit_depth = 0, color_type = 0;
  png_get_IHDR(png, info, width, height, &bit_depth, &color_type, nullptr, nullptr, nullptr);
  const bool color = mode == ColorMode::kColor;
  if (bit_depth == 16) png_set_strip_16(png);  // keeps the high byte, as OpenCV does
  png_set_strip_alpha(png);
  if (color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if ((color_type & PNG_COLOR_MASK_COLOR) == 0 && bit_depth < 8)
    png_set_expand_gray_1_2_4_to_8(png);
  if ((color_type & PNG_COLOR_MASK_COLOR) != 0 && color) {
    png_set_bgr(png);
  } else if (color) {
    png_set_gray_to_rgb(png);
  } else {
    png_set_rgb_to_gray(png, 1, 0.299, 0.587);
  }
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  return png_get_rowbytes(png, info) == static_cast<size_t>(*width) * (color ? 3 : 1);
}

bool ReadRows(png_structp png, png_infop end_info, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png)) != 0) return false;
  png_read_image(png, rows);
  png_read_end(png, end_info);
  return true;
}

bool WritePixels(png_structp png, png_infop info, const cv::Mat& image, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png)) != 0) return false;
  // OpenCV's defaults when no compression parameter is given (imgcodecs grfmt_png.cpp).
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
  png_set_compression_level(png, Z_BEST_SPEED);
  png_set_compression_strategy(png, Z_RLE);
  const int channels = image.channels();
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.cols),
               static_cast<png_uint_32>(image.rows), image.depth() == CV_8U ? 8 : 16,
               channels == 1   ? PNG_COLOR_TYPE_GRAY
               : channels == 3 ? PNG_COLOR_TYPE_RGB
                               : PNG_COLOR_TYPE_RGBA,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  png_set_bgr(png);
  // 16-bit samples: PNG stores them big-endian, cv::Mat in the machine's order.
  if constexpr (std::endian::native == std::endian::little) png_set_swap(png);
  png_write_image(png, rows);
  png_write_end(png, info);
  return true;
}

}  // namespace

bool LooksLikePng(const uint8_t* data, size_t size) {
  return size >= sizeof(kSignature) && std::memcmp(data, kSignature, sizeof(kSignature)) == 0;
}

bool PngDimensions(const uint8_t* data, size_t size, uint32_t* width, uint32_t* height) {
  // Signature (8 bytes), then the IHDR chunk: length (4), "IHDR", width and height big-endian.
  if (!LooksLikePng(data, size) || size < 24 || std::memcmp(data + 12, "IHDR", 4) != 0)
    return false;
  auto big_endian = [&](size_t at) {
    return (uint32_t{data[at]} << 24) | (uint32_t{data[at + 1]} << 16) |
           (uint32_t{data[at + 2]} << 8) | uint32_t{data[at + 3]};
  };
  *width = big_endian(16);
  *height = big_endian(20);
  return true;
}

cv::Mat DecodePng(const uint8_t* data, size_t size, ColorMode mode, std::vector<uint8_t>* exif) {
  if (exif != nullptr) exif->clear();
  if (!LooksLikePng(data, size)) return cv::Mat();
  png_structp png =
      png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, JumpOnError, IgnoreWarning);
  if (png == nullptr) return cv::Mat();
  png_infop info = png_create_info_struct(png);
  png_infop end_info = png_create_info_struct(png);
  cv::Mat pixels;
  bool ok = false;
  ReadState state{data, size, 0};
  png_uint_32 width = 0, height = 0;
  if (info != nullptr && end_info != nullptr) {
    png_set_read_fn(png, &state, ReadFromMemory);
    ok = ReadHeader(png, info, mode, &width, &height) && width > 0 && height > 0 &&
         width <= INT32_MAX && height <= INT32_MAX;
  }
  if (ok) {
    pixels.create(static_cast<int>(height), static_cast<int>(width),
                  mode == ColorMode::kColor ? CV_8UC3 : CV_8UC1);
    std::vector<png_bytep> rows(height);
    for (png_uint_32 y = 0; y < height; ++y) rows[y] = pixels.ptr(static_cast<int>(y));
    ok = ReadRows(png, end_info, rows.data());
  }
  // The eXIf chunk may come before the image data (info) or after it (end_info).
  png_uint_32 exif_size = 0;
  png_bytep exif_data = nullptr;
  if (ok && exif != nullptr) {
    if (png_get_valid(png, info, PNG_INFO_eXIf) != 0) {
      png_get_eXIf_1(png, info, &exif_size, &exif_data);
    } else if (png_get_valid(png, end_info, PNG_INFO_eXIf) != 0) {
      png_get_eXIf_1(png, end_info, &exif_size, &exif_data);
    }
    if (exif_data != nullptr) exif->assign(exif_data, exif_data + exif_size);
  }
  png_destroy_read_struct(&png, &info, &end_info);
  return ok ? pixels : cv::Mat();
}

bool EncodePng(const cv::Mat& image, std::vector<uint8_t>* png_data) {
  const int channels = image.channels();
  if (image.empty() || (image.depth() != CV_8U && image.depth() != CV_16U) ||
      (channels != 1 && channels != 3 && channels != 4)) {
    return false;
  }
  png_structp png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, JumpOnError, IgnoreWarning);
  if (png == nullptr) return false;
  png_infop info = png_create_info_struct(png);
  std::vector<png_bytep> rows(image.rows);
  for (int y = 0; y < image.rows; ++y) rows[y] = const_cast<png_bytep>(image.ptr(y));
  png_data->clear();
  bool ok = false;
  if (info != nullptr) {
    png_set_write_fn(png, png_data, WriteToVector, FlushNothing);
    ok = WritePixels(png, info, image, rows.data());
  }
  png_destroy_write_struct(&png, &info);
  return ok;
}

}  // namespace varsfm
