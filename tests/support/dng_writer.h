#pragma once
// Minimal DNG files for tests (Adobe DNG specification 1.4): an uncompressed 16-bit RGGB Bayer
// mosaic of a picture, with the tags LibRaw needs to develop it, as a phone's raw file holds it.
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace varsfm::testing {

// `bgr` (8-bit, 3 channels, even width and height) sampled into an RGGB mosaic, stored as given
// with TIFF `orientation` (1-8) and, when `focal_35mm` > 0, an EXIF FocalLengthIn35mmFilm tag.
std::vector<uint8_t> EncodeDng(const cv::Mat& bgr, int orientation = 1, int focal_35mm = 0);

}  // namespace varsfm::testing
