#pragma once
// Structural similarity (Wang, Bovik, Sheikh, Simoncelli 2004, eq. 13) between a rendering and
// a photo, as the view-synthesis literature reports it beside PSNR: an 11 x 11 Gaussian window
// (sigma 1.5), C1 = (0.01 L)^2, C2 = (0.03 L)^2 with L = 255, each colour channel separately,
// averaged.
#include <opencv2/core.hpp>

namespace varsfm {

// Mean SSIM over the pixels of `mask` (8-bit, non-zero: scored) whose whole window lies inside
// the mask, so the black of uncovered pixels never enters a window; when no such pixel exists,
// over the mask itself. `a` and `b`: 8-bit, same size and channel count. Returns 0 for an empty
// mask.
double MaskedSsim(const cv::Mat& a, const cv::Mat& b, const cv::Mat& mask);

}  // namespace varsfm
