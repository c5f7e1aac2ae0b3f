#pragma once
// JPEG decoding and encoding with libjpeg-turbo's TurboJPEG API. varsfm reads JPEGs directly
// instead of through OpenCV's imgcodecs because linking imgcodecs pulls in ~210 shared
// libraries (GDAL, codecs for formats varsfm rarely sees) whose loading dominated the start-up
// of every command. The settings match OpenCV's libjpeg path, so pixels are bit-identical.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "varsfm/image/image_file.h"

namespace varsfm {

// Decodes the JPEG `data` into 8-bit grey or BGR pixels as stored (no EXIF orientation) with
// the accurate integer DCT and fancy upsampling, which is what cv::imdecode does. Returns an
// empty Mat when the data cannot be decoded (corrupt or not a JPEG), and nothing for colour
// spaces TurboJPEG cannot turn into BGR (CMYK/YCCK): the caller hands those to OpenCV, which
// converts them itself.
std::optional<cv::Mat> DecodeJpeg(const uint8_t* data, size_t size, ColorMode mode);

// The width and height the JPEG `data`'s frame header declares; false when it has none.
bool JpegDimensions(const uint8_t* data, size_t size, int* width, int* height);

// Encodes 8-bit grey, BGR or BGRA `image` (alpha dropped) as a baseline JPEG of `quality`
// (0-100) with 4:2:0 chroma subsampling (grey: one component) and the accurate DCT, as
// cv::imencode does. Returns false for other image types.
bool EncodeJpeg(const cv::Mat& image, int quality, std::vector<uint8_t>* jpeg);

}  // namespace varsfm
