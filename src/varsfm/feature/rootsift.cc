#include "varsfm/feature/rootsift.h"

#include <algorithm>
#include <cmath>

#include "varsfm/util/error.h"

namespace varsfm {

FeatureDescriptors RootSiftDescriptors(const cv::Mat& descriptors) {
  if (descriptors.empty()) return FeatureDescriptors(0, 128);
  if (descriptors.type() != CV_32F) Fail("RootSIFT expects float descriptors");
  FeatureDescriptors out(descriptors.rows, descriptors.cols);
  for (int r = 0; r < descriptors.rows; ++r) {
    const float* row = descriptors.ptr<float>(r);
    double l1 = 0;
    for (int c = 0; c < descriptors.cols; ++c) l1 += std::abs(row[c]);
    // An all-zero descriptor (uniform patch) stays zero rather than dividing by zero.
    const double inv_l1 = l1 > 0 ? 1.0 / l1 : 0.0;
    for (int c = 0; c < descriptors.cols; ++c) {
      const double value = 512.0 * std::sqrt(std::abs(row[c]) * inv_l1);
      out(r, c) = static_cast<uint8_t>(std::min(255.0, std::round(value)));
    }
  }
  return out;
}

}  // namespace varsfm
