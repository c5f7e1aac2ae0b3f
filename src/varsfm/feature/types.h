#pragma once
// Feature types, laid out as COLMAP stores them (keypoints table: 6 float32 columns per row;
// descriptors table: 128 uint8 columns per row).
//
// Pixel convention everywhere in varsfm (as in COLMAP): the top-left corner of the top-left
// pixel is (0, 0), so the centre of that pixel is (0.5, 0.5). OpenCV's keypoints put the
// pixel centre at (0, 0) and are shifted by +0.5 when they enter varsfm.
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "varsfm/util/types.h"

namespace varsfm {

struct FeatureKeypoint {
  FeatureKeypoint() = default;
  FeatureKeypoint(float x_, float y_) : x(x_), y(y_) {}
  // From a SIFT frame: scale (pixels) and orientation (radians), stored as the affine shape
  // A = scale * R(orientation), as COLMAP does.
  FeatureKeypoint(float x_, float y_, float scale, float orientation)
      : x(x_), y(y_),
        a11(scale * std::cos(orientation)), a12(-scale * std::sin(orientation)),
        a21(scale * std::sin(orientation)), a22(scale * std::cos(orientation)) {}

  float Scale() const { return 0.5f * (std::hypot(a11, a21) + std::hypot(a12, a22)); }
  float Orientation() const { return std::atan2(a21, a11); }

  float x = 0, y = 0;
  float a11 = 1, a12 = 0, a21 = 0, a22 = 1;
};
using FeatureKeypoints = std::vector<FeatureKeypoint>;

// One row per keypoint, 128 columns for SIFT.
using FeatureDescriptors = Eigen::Matrix<uint8_t, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct FeatureMatch {
  point2D_t point2D_idx1 = kInvalidPoint2DIdx;
  point2D_t point2D_idx2 = kInvalidPoint2DIdx;
  bool operator==(const FeatureMatch&) const = default;
};
using FeatureMatches = std::vector<FeatureMatch>;

}  // namespace varsfm
