#pragma once
// The EXIF tags varsfm uses: the focal length, turned into pixels so it can serve as a prior
// for the per-image intrinsics (never required: cameras are self-calibrated), and the
// orientation, which says how to turn the stored pixels upright.
#include <cstddef>
#include <cstdint>
#include <optional>

namespace varsfm {

// What precedes EXIF data in a JPEG APP1 segment, and what libexif looks for.
inline constexpr uint8_t kExifHeader[] = {'E', 'x', 'i', 'f', 0, 0};

// The focal length in pixels of an image of `width` x `height` pixels (as displayed, after the
// EXIF orientation) from the EXIF block of `data` (a whole JPEG file, or raw EXIF data), or
// nothing when the tags are absent or implausible. Uses, in order:
//  1. FocalLengthIn35mmFilm: the focal length a 36x24 mm frame with the same field of view
//     would have; the equivalence is defined on the diagonal (CIPA DC-008), so
//     f_px = f35 * diagonal_px / 43.27 mm.
//  2. FocalLength (mm) * FocalPlaneXResolution (pixels per unit of FocalPlaneResolutionUnit),
//     scaled by the ratio of the image size to PixelX/YDimension when the image was resized.
std::optional<double> ExifFocalLengthPixels(const uint8_t* data, size_t size, int width,
                                            int height);

// Rule 1 above on its own: the focal length in pixels of a `width` x `height` image whose
// 35 mm film equivalent is `f35_mm`; nothing for a non-positive or implausible value.
std::optional<double> FocalPixelsFrom35mmEquivalent(double f35_mm, int width, int height);

// The Orientation tag (TIFF/EXIF 0x0112, IFD0) of the EXIF block of `data` (a whole JPEG file,
// or EXIF data starting with the "Exif\0\0" header): 1 (upright, also when absent or invalid)
// to 8; see ApplyExifOrientation in image/orientation.h.
int ExifOrientation(const uint8_t* data, size_t size);

}  // namespace varsfm
