#pragma once
// Identifiers shared across modules. They follow COLMAP: ids start at 1, and a pair of images
// is encoded as one 64-bit pair id (see io/database.h).
#include <cstdint>
#include <limits>

#include <Eigen/Core>

namespace varsfm {

using camera_t = uint32_t;
using image_t = uint32_t;
using point2D_t = uint32_t;
using point3D_t = uint64_t;
using image_pair_t = uint64_t;

inline constexpr image_t kInvalidImageId = std::numeric_limits<image_t>::max();
inline constexpr point2D_t kInvalidPoint2DIdx = std::numeric_limits<point2D_t>::max();
inline constexpr point3D_t kInvalidPoint3DId = std::numeric_limits<point3D_t>::max();

using Vector2d = Eigen::Vector2d;
using Vector3d = Eigen::Vector3d;
using Matrix3d = Eigen::Matrix3d;
using Matrix34d = Eigen::Matrix<double, 3, 4>;

}  // namespace varsfm
