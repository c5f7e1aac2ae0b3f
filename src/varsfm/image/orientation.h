#pragma once
// Turning decoded pixels upright by the EXIF orientation, as cv::imread does: cameras store the
// sensor's rows and record the rotation instead of rotating the pixels, and the rest of varsfm
// (intrinsics, the EXIF focal prior, texturing) works on the image as displayed.
#include <opencv2/core.hpp>

namespace varsfm {

// Applies EXIF `orientation` (1-8, see image/exif.h; other values leave the image as is) to
// `image` in place, with the same transposes and flips as OpenCV's ApplyExifOrientation so the
// result is identical.
void ApplyExifOrientation(int orientation, cv::Mat* image);

}  // namespace varsfm
