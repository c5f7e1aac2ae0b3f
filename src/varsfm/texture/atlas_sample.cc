#include "varsfm/texture/atlas_sample.h"

#include <algorithm>
#include <cmath>

namespace varsfm {

cv::Vec3f SampleAtlas(const cv::Mat& page, double x, double y) {
  x -= 0.5;
  y -= 0.5;
  const int x0 = std::clamp(static_cast<int>(std::floor(x)), 0, page.cols - 1);
  const int y0 = std::clamp(static_cast<int>(std::floor(y)), 0, page.rows - 1);
  const int x1 = std::min(x0 + 1, page.cols - 1), y1 = std::min(y0 + 1, page.rows - 1);
  const float ax = static_cast<float>(std::clamp(x - x0, 0.0, 1.0));
  const float ay = static_cast<float>(std::clamp(y - y0, 0.0, 1.0));
  const cv::Vec3b* r0 = page.ptr<cv::Vec3b>(y0);
  const cv::Vec3b* r1 = page.ptr<cv::Vec3b>(y1);
  const cv::Vec3f top = (1 - ax) * cv::Vec3f(r0[x0]) + ax * cv::Vec3f(r0[x1]);
  const cv::Vec3f bottom = (1 - ax) * cv::Vec3f(r1[x0]) + ax * cv::Vec3f(r1[x1]);
  return (1 - ay) * top + ay * bottom;
}

}  // namespace varsfm
