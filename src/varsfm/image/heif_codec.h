#pragma once
// HEIF photos -- HEIC, the iPhone's default format, and AVIF -- decoded with libheif (its HEVC
// and AV1 decoders are Debian's libde265 and dav1d). A phone user's photo folder is often all
// HEIC; without a decoder the whole capture would have to be converted first.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

#include <opencv2/core.hpp>

#include "varsfm/image/image_file.h"

namespace varsfm {

// Whether `path` names a HEIF photo (.heic, .heif, .avif; any case).
bool IsHeifPhotoName(const std::filesystem::path& path);

// Whether `data` starts with an ISO base media file's 'ftyp' box naming a HEIF brand (heic,
// heix, mif1, avif, ...), as libheif's own check says.
bool LooksLikeHeif(const uint8_t* data, size_t size);

// The primary image of the HEIF `data`, upright: the file's own transformations (HEIF's rotation,
// mirror and crop properties, which libheif applies; its EXIF orientation only restates them)
// as 8-bit grey or BGR pixels. Empty when it cannot be decoded. Throws varsfm::Error (one line
// naming `path`) for an image declaring more than kMaxImagePixels.
cv::Mat DecodeHeif(const std::filesystem::path& path, const uint8_t* data, size_t size,
                   ColorMode mode);

// The primary image's EXIF block, as EXIF data starting with the "Exif\0\0" header
// (exif.h reads it); empty when there is none or `data` is not a readable HEIF file.
std::vector<uint8_t> HeifExif(const uint8_t* data, size_t size);

}  // namespace varsfm
