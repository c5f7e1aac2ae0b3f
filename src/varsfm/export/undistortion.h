#pragma once
// Undistortion of one image to an ideal pinhole camera, as the consumers of a sparse model that
// know only PINHOLE cameras need it (3D Gaussian Splatting's COLMAP loader, most NeRF code).
//
// The pinhole camera keeps the image's focal lengths (fx = f, fy = e f) and drops skew and
// radial distortion. Its size and principal point are chosen as COLMAP's image_undistorter does
// with its default blank_pixels = 0: the largest axis-aligned rectangle inside the undistorted
// image of the photo's border, so that every output pixel comes from the photo (no black
// border for a splatting loss to fit).
#include <opencv2/core.hpp>

#include "varsfm/camera/camera.h"

namespace varsfm {

// The pinhole camera an image with `camera` is undistorted to. Throws varsfm::Error when the
// distortion is so strong that no valid rectangle of at least 2 x 2 pixels remains.
Camera UndistortedPinholeCamera(const Camera& camera);

// A pixel of the distorted image (COLMAP convention: (0, 0) is the top-left corner of the
// top-left pixel) in the undistorted image of `pinhole`.
Eigen::Vector2d UndistortPixel(const Camera& camera, const Camera& pinhole,
                               const Eigen::Vector2d& pixel);

// Resamples `image` (any channel count, 8-bit) to `pinhole`'s size by bilinear interpolation:
// each output pixel centre is mapped through the pinhole to the ray it sees and then through
// `camera`'s full model into the photo.
cv::Mat UndistortImage(const cv::Mat& image, const Camera& camera, const Camera& pinhole);

}  // namespace varsfm
