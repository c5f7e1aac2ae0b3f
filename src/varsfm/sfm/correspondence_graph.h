#pragma once
// Which 2D points correspond across images, from the verified matches of every pair. The mapper
// follows these links to find an image's 2D-3D correspondences through tracks (Algorithm 2 of
// El Hazzat et al., generalised from the previous two images to every registered image).
#include <map>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "varsfm/feature/types.h"
#include "varsfm/util/types.h"

namespace varsfm {

struct Correspondence {
  image_t image_id = kInvalidImageId;
  point2D_t point2D_idx = kInvalidPoint2DIdx;
};

class CorrespondenceGraph {
 public:
  // Declares an image and its number of 2D points (before adding pairs).
  void AddImage(image_t image_id, size_t num_points2D);
  // Adds the verified matches of a pair, in both directions, with the fundamental matrix they
  // are the inliers of (x2^T F x1 = 0 for image_id1 -> image_id2), when verification found one.
  void AddImagePair(image_t image_id1, image_t image_id2, const FeatureMatches& matches,
                    const std::optional<Eigen::Matrix3d>& F = std::nullopt);

  bool ExistsImage(image_t image_id) const { return images_.count(image_id) > 0; }
  std::vector<image_t> ImageIds() const;
  const std::vector<Correspondence>& CorrespondencesOf(image_t image_id,
                                                       point2D_t point2D_idx) const {
    return images_.at(image_id).correspondences.at(point2D_idx);
  }
  size_t NumPoints2D(image_t image_id) const { return images_.at(image_id).correspondences.size(); }
  // Number of 2D points of the image with at least one correspondence.
  size_t NumObservedPoints2D(image_t image_id) const;

  // The images that share verified matches with the image, in id order.
  const std::vector<image_t>& NeighborsOf(image_t image_id) const {
    return images_.at(image_id).neighbors;
  }

  // The verified matches of one pair, for the order asked (empty if none).
  FeatureMatches MatchesBetween(image_t image_id1, image_t image_id2) const;
  // The pair's verified F for the order asked (x2^T F x1 = 0), if it was given.
  std::optional<Eigen::Matrix3d> FundamentalMatrix(image_t image_id1, image_t image_id2) const;
  // All pairs with their number of verified matches (image_id1 < image_id2).
  const std::map<std::pair<image_t, image_t>, size_t>& PairCounts() const { return pair_counts_; }

 private:
  struct ImageEntry {
    std::vector<std::vector<Correspondence>> correspondences;  // per 2D point
    std::vector<image_t> neighbors;                            // sorted
  };
  std::map<image_t, ImageEntry> images_;
  std::map<std::pair<image_t, image_t>, size_t> pair_counts_;
  // By (smaller id, larger id), for that order.
  std::map<std::pair<image_t, image_t>, Eigen::Matrix3d> fundamentals_;
};

}  // namespace varsfm
