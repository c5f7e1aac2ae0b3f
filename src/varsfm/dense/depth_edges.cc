#include "varsfm/dense/depth_edges.h"

#include <vector>

#include <opencv2/imgproc.hpp>

#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

// The pixels without depth that belong to the open background (255), the others 0.
cv::Mat OpenBackground(const DepthMap& map, int min_gap_px, double large_fraction) {
  const cv::Mat depth(map.height, map.width, CV_32F, const_cast<float*>(map.depth.data()));
  cv::Mat gap = depth <= 0;
  if (min_gap_px > 1)
    cv::morphologyEx(gap, gap, cv::MORPH_OPEN, cv::Mat::ones(min_gap_px, min_gap_px, CV_8U),
                     {-1, -1}, 1, cv::BORDER_CONSTANT, 0);
  cv::Mat labels;
  const int count = cv::connectedComponents(gap, labels, 8, CV_32S);
  std::vector<uchar> open(count, 0);
  for (int x = 0; x < labels.cols; ++x)
    open[labels.at<int>(0, x)] = open[labels.at<int>(labels.rows - 1, x)] = 255;
  for (int y = 0; y < labels.rows; ++y)
    open[labels.at<int>(y, 0)] = open[labels.at<int>(y, labels.cols - 1)] = 255;
  if (large_fraction > 0) {  // 0: only the regions that reach the border
    std::vector<size_t> area(count, 0);
    for (int y = 0; y < labels.rows; ++y)
      for (int x = 0; x < labels.cols; ++x) ++area[labels.at<int>(y, x)];
    for (int k = 1; k < count; ++k)
      if (area[k] >= large_fraction * labels.total()) open[k] = 255;
  }
  open[0] = 0;  // label 0: every pixel that is no gap
  for (int y = 0; y < labels.rows; ++y)
    for (int x = 0; x < labels.cols; ++x) gap.at<uchar>(y, x) = open[labels.at<int>(y, x)];
  return gap;
}

}  // namespace

size_t ErodeDepthEdges(const DepthEdgeOptions& options, DepthMap* map) {
  const int r = options.erosion_px;
  if (r <= 0 || map->depth.empty()) return 0;
  cv::Mat near_background;
  cv::dilate(OpenBackground(*map, options.min_gap_px, options.large_gap_fraction), near_background,
             cv::Mat::ones(2 * r + 1, 2 * r + 1, CV_8U), {-1, -1}, 1, cv::BORDER_CONSTANT, 0);
  size_t dropped = 0;
  for (int y = 0; y < map->height; ++y)
    for (int x = 0; x < map->width; ++x) {
      float& d = map->depth[map->Index(x, y)];
      if (d > 0 && near_background.at<uchar>(y, x)) d = 0, ++dropped;
    }
  return dropped;
}

void DepthEdgeOptions::Check() const {
  CheckInRange("--dense-edge-erosion", erosion_px, 0, 16);
  CheckInRange("depth edge min_gap_px", min_gap_px, 1, 64);
  CheckInRange("depth edge large_gap_fraction", large_gap_fraction, 0.0, 1.0);
}

}  // namespace varsfm
