#include "varsfm/texture/atlas_fill.h"

#include <vector>

#include <opencv2/imgproc.hpp>

namespace varsfm {

void BleedAtlasBackground(cv::Mat* page, const cv::Mat& filled, int rings) {
  if (rings <= 0 || cv::countNonZero(filled) == 0) return;
  // distanceTransform measures the distance to the nearest zero texel: zeros = filled texels.
  const cv::Mat empty = filled == 0;
  cv::Mat distance, labels;
  cv::distanceTransform(empty, distance, labels, cv::DIST_L2, cv::DIST_MASK_5,
                        cv::DIST_LABEL_PIXEL);
  // Each filled texel carries its own label; record the colour of every label.
  std::vector<cv::Vec3b> colour_of_label(static_cast<size_t>(page->total()) + 1);
  for (int y = 0; y < page->rows; ++y) {
    const uchar* e = empty.ptr<uchar>(y);
    const int* l = labels.ptr<int>(y);
    const cv::Vec3b* c = page->ptr<cv::Vec3b>(y);
    for (int x = 0; x < page->cols; ++x)
      if (!e[x]) colour_of_label[l[x]] = c[x];
  }
  for (int y = 0; y < page->rows; ++y) {
    const uchar* e = empty.ptr<uchar>(y);
    const int* l = labels.ptr<int>(y);
    const float* d = distance.ptr<float>(y);
    cv::Vec3b* c = page->ptr<cv::Vec3b>(y);
    for (int x = 0; x < page->cols; ++x)
      if (e[x] && d[x] <= rings) c[x] = colour_of_label[l[x]];
  }
}

}  // namespace varsfm
