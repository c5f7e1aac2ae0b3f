#pragma once
// HEIC files for tests, written with libheif's x265 encoder: what an iPhone stores, including the
// rotation a phone held upright writes as a transformation property, and its EXIF block.
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace varsfm::testing {

// `bgr` (8-bit, 3 channels) as a HEIC file of `quality` (0-100), stored as given and marked with
// `orientation` (EXIF's numbering, 1-8; libheif writes it as HEIF's rotation and mirror
// properties, which a reader applies), with `exif` (EXIF data starting with "Exif\0\0", or
// nothing) as its EXIF block. Fails the calling test (ADD_FAILURE) and returns nothing when
// libheif cannot encode.
std::vector<uint8_t> EncodeHeic(const cv::Mat& bgr, int quality = 90, int orientation = 1,
                                const std::vector<uint8_t>& exif = {});

}  // namespace varsfm::testing
