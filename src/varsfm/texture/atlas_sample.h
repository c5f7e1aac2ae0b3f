#pragma once
// Bilinear lookup in an atlas page, as the renderer and viewers sample it.
#include <opencv2/core.hpp>

namespace varsfm {

// `page`: BGR 8-bit. Position (x, y) in pixels, texel centres at i + 0.5 (the pixel convention
// of the photos the atlas was cut from), clamped at the page border.
cv::Vec3f SampleAtlas(const cv::Mat& page, double x, double y);

}  // namespace varsfm
