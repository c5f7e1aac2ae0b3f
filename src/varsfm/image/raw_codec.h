#pragma once
// Camera raw photos (DNG -- a phone's ProRAW or Expert RAW too -- and the raw formats of Canon,
// Nikon, Sony, Fujifilm, Olympus, Panasonic, Pentax, Samsung), developed with LibRaw as dcraw
// would by default: the camera's white balance, AHD demosaicing, sRGB, 8 bits, its orientation
// applied. Raw files are told by their extension: most are TIFF files inside.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>

#include <opencv2/core.hpp>

#include "varsfm/image/image_file.h"

namespace varsfm {

// Whether `path` names a camera raw file (.dng, .cr2, .cr3, .nef, .arw, .raf, .orf, .rw2, .pef,
// .srw; any case).
bool IsRawPhotoName(const std::filesystem::path& path);

// The raw photo `data` developed into 8-bit grey or BGR pixels, upright. Empty when LibRaw cannot
// read it. Throws varsfm::Error (one line naming `path`) for a sensor of more than kMaxImagePixels.
cv::Mat DecodeRaw(const std::filesystem::path& path, const uint8_t* data, size_t size,
                  ColorMode mode);

// The focal length in 35 mm film equivalent (mm) the raw file records (EXIF
// FocalLengthIn35mmFilm), or nothing.
std::optional<double> RawFocalLength35mm(const uint8_t* data, size_t size);

}  // namespace varsfm
