#pragma once
// Similarity alignment y = s R x + t of estimated camera centres onto true ones, the standard
// way to compare a reconstruction (defined up to a similarity) with ground truth. Least squares
// by Umeyama (PAMI 1991), optionally inside RANSAC so a few badly placed cameras do not drag
// the frame and hide in everybody's error.
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "varsfm/util/random.h"

namespace varsfm {

struct Sim3d {
  double scale = 1.0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Eigen::Vector3d operator*(const Eigen::Vector3d& x) const {
    return scale * (rotation * x) + translation;
  }
  Sim3d Inverse() const;
};

struct AlignmentOptions {
  // <= 0: plain least squares over all points. > 0: RANSAC over 3-point samples; a point is an
  // inlier when its aligned distance is below this (in the target's units), and the result is
  // the least-squares fit to the largest inlier set.
  double inlier_threshold = 0.0;
  int max_trials = 2000;  // all triples are tried when there are no more than this
  uint64_t seed = kDefaultSeed;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

struct AlignmentResult {
  bool success = false;  // false: fewer than 3 points, or all (nearly) collinear
  Sim3d sim;             // target ~ sim * source
  std::vector<bool> inliers;
  size_t num_inliers = 0;
};

AlignmentResult AlignSimilarity(const std::vector<Eigen::Vector3d>& source,
                                const std::vector<Eigen::Vector3d>& target,
                                const AlignmentOptions& options = {});

}  // namespace varsfm
