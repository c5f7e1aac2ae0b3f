#pragma once
// Undistortion of one image to an ideal pinhole camera, as the consumers of a sparse model that
// know only PINHOLE cameras need it (3D Gaussian Splatting's COLMAP loader, most NeRF code).
//
// The pinhole camera keeps the image's focal lengths (fx = f, fy = e f) and drops skew and
// radial distortion. Its size and principal point are chosen as COLMAP's image_undistorter does
// with its default blank_pixels = 0: the largest axis-aligned rectangle inside the undistorted
// image of the photo's border, so that every output pixel comes from the photo (no black
// border for a splatting loss to fit). Centred, the rectangle is instead the largest one inside
// that border whose centre is the principal point: for a consumer that takes a camera's field of
// view from its focal length and size and ignores cx, cy (3D Gaussian Splatting's reference
// loader builds a symmetric frustum), the image then is exactly the pinhole it assumes.
#include <opencv2/core.hpp>

#include "varsfm/camera/camera.h"

namespace varsfm {

// Where the undistorted image's principal point lies: where the photo's maps to in the largest
// rectangle (COLMAP's cx, cy), or at the centre of the largest rectangle centred on it.
enum class PrincipalPointPlacement { kKept, kCentred };

// The pinhole camera an image with `camera` is undistorted to. Throws varsfm::Error when the
// distortion is so strong that no valid rectangle of at least 2 x 2 pixels remains (centred:
// also when the principal point lies outside the photo or within a pixel of its border).
Camera UndistortedPinholeCamera(const Camera& camera,
                                PrincipalPointPlacement placement = PrincipalPointPlacement::kKept);

// A pixel of the distorted image (COLMAP convention: (0, 0) is the top-left corner of the
// top-left pixel) in the undistorted image of `pinhole`.
Eigen::Vector2d UndistortPixel(const Camera& camera, const Camera& pinhole,
                               const Eigen::Vector2d& pixel);

// Resamples `image` (any channel count, 8-bit) to `pinhole`'s size by bicubic interpolation:
// each output pixel centre is mapped through the pinhole to the ray it sees and then through
// `camera`'s full model into the photo.
cv::Mat UndistortImage(const cv::Mat& image, const Camera& camera, const Camera& pinhole);

}  // namespace varsfm
