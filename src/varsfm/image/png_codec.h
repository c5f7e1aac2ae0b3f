#pragma once
// PNG decoding and encoding with libpng, for the same reason as jpeg_codec.h: reading and
// writing the two formats varsfm uses without linking OpenCV's imgcodecs. The libpng
// transformations are the ones OpenCV applies, so pixels (and written files) are identical.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "varsfm/image/image_file.h"

namespace varsfm {

// True when `data` starts with the PNG signature.
bool LooksLikePng(const uint8_t* data, size_t size);

// The width and height the PNG `data`'s IHDR chunk declares (the first chunk, by the PNG
// specification); false when the data is too short or does not start with one.
bool PngDimensions(const uint8_t* data, size_t size, uint32_t* width, uint32_t* height);

// Decodes the PNG `data` into 8-bit grey or BGR pixels as cv::imdecode(IMREAD_GRAYSCALE /
// IMREAD_COLOR) does: 16-bit samples keep their high byte, alpha is dropped, palettes and low
// bit depths are expanded, colour becomes grey with libpng's weights (0.299, 0.587, 0.114).
// Returns an empty Mat when the data is not a decodable PNG. The pixels are as stored; when
// `exif` is given it receives the payload of the eXIf chunk (raw TIFF-format EXIF, empty when
// there is none), which holds the orientation.
cv::Mat DecodePng(const uint8_t* data, size_t size, ColorMode mode,
                  std::vector<uint8_t>* exif = nullptr);

// Encodes 8- or 16-bit grey, BGR or BGRA `image` as PNG with OpenCV's default settings (sub
// filter, fastest zlib level, RLE strategy: quick, and the files match cv::imwrite's). Returns
// false for other image types.
bool EncodePng(const cv::Mat& image, std::vector<uint8_t>* png);

}  // namespace varsfm
