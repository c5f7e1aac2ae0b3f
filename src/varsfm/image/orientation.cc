#include "varsfm/image/orientation.h"

namespace varsfm {

void ApplyExifOrientation(int orientation, cv::Mat* image) {
  // Orientation names the position of row 0 and column 0 in the displayed image (EXIF 2.3).
  switch (orientation) {
    case 2:  // top-right: mirrored horizontally
      cv::flip(*image, *image, 1);
      break;
    case 3:  // bottom-right: rotated 180 degrees
      cv::flip(*image, *image, -1);
      break;
    case 4:  // bottom-left: mirrored vertically
      cv::flip(*image, *image, 0);
      break;
    case 5:  // left-top: transposed
      cv::transpose(*image, *image);
      break;
    case 6:  // right-top: rotated 90 degrees clockwise to display
      cv::transpose(*image, *image);
      cv::flip(*image, *image, 1);
      break;
    case 7:  // right-bottom: transverse
      cv::transpose(*image, *image);
      cv::flip(*image, *image, -1);
      break;
    case 8:  // left-bottom: rotated 90 degrees counter-clockwise to display
      cv::transpose(*image, *image);
      cv::flip(*image, *image, 0);
      break;
    default:  // 1 (top-left) or unknown: already upright
      break;
  }
}

}  // namespace varsfm
