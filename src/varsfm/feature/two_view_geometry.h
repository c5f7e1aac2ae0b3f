#pragma once
// The verified geometry of an image pair, as COLMAP's two_view_geometries table stores it: the
// result of geometric verification (matching/) and a row of the workspace database (io/), so it
// lives beside the feature matches it holds.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "varsfm/feature/types.h"

namespace varsfm {

struct TwoViewGeometry {
  // Same values as COLMAP's TwoViewGeometry::ConfigurationType.
  enum Config : int {
    kUndefined = 0,
    kDegenerate = 1,
    kCalibrated = 2,
    kUncalibrated = 3,  // general configuration, F only
    kPlanar = 4,
    kPanoramic = 5,
    kPlanarOrPanoramic = 6,
    kWatermark = 7,
    kMultiple = 8,
  };

  int config = kUndefined;
  Eigen::Matrix3d F = Eigen::Matrix3d::Zero();  // x2^T F x1 = 0, pixel coordinates
  Eigen::Matrix3d E = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();  // x2 ~ H x1
  Eigen::Quaterniond cam2_from_cam1_rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d cam2_from_cam1_translation = Eigen::Vector3d::Zero();
  FeatureMatches inlier_matches;
};

}  // namespace varsfm
