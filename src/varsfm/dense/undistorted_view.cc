#include "varsfm/dense/undistorted_view.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "varsfm/camera/image_size.h"
#include "varsfm/util/error.h"

namespace varsfm {

UndistortedView UndistortImage(const cv::Mat& image, const Camera& camera, double scale) {
  if (image.empty()) Fail("densify: empty image for camera {}", camera.camera_id);
  UndistortedView out;
  const int width = std::max(1, static_cast<int>(std::lround(image.cols * scale)));
  const int height = std::max(1, static_cast<int>(std::lround(image.rows * scale)));
  const double sx = static_cast<double>(width) / image.cols;
  Camera sized = camera;  // the image's own size: the camera may be given for another
  sized.width = image.cols;
  sized.height = image.rows;
  const Camera scaled = sized.Resized(width, height);
  cv::Mat source = image;
  if (width != image.cols || height != image.rows)
    cv::resize(image, source, cv::Size(width, height), 0, 0, cv::INTER_AREA);
  out.K = scaled.K();
  out.scale = sx;
  if (!scaled.HasDistortion()) {
    out.color = source.clone();
  } else {
    const Eigen::Matrix3d K_inv = out.K.inverse();
    cv::Mat map_x(height, width, CV_32F), map_y(height, width, CV_32F);
    cv::parallel_for_(cv::Range(0, height), [&](const cv::Range& rows) {
      for (int r = rows.start; r < rows.end; ++r)
        for (int c = 0; c < width; ++c) {
          const Eigen::Vector3d n = K_inv * Eigen::Vector3d(c + 0.5, r + 0.5, 1.0);
          const Eigen::Vector2d x = scaled.NormalizedToImage(n.hnormalized());
          // OpenCV samples with pixel centres at integers.
          map_x.at<float>(r, c) = static_cast<float>(x.x() - 0.5);
          map_y.at<float>(r, c) = static_cast<float>(x.y() - 0.5);
        }
    });
    cv::remap(source, out.color, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
  }
  if (out.color.channels() == 3)
    cv::cvtColor(out.color, out.gray, cv::COLOR_BGR2GRAY);
  else
    out.gray = out.color, cv::cvtColor(out.gray, out.color, cv::COLOR_GRAY2BGR);
  return out;
}

UndistortedView UndistortAtMostSize(const cv::Mat& image, const Camera& camera,
                                    int max_image_size) {
  return UndistortImage(image, camera, SizeWithin(camera, max_image_size).scale);
}

}  // namespace varsfm
