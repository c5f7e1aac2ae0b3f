#pragma once
// The spatial neighbourhood of point correspondences over which graph-cut RANSAC's labelling
// prefers equal labels (Barath & Matas, "Graph-Cut RANSAC", CVPR 2018, sec. 3): two
// correspondences are neighbours when they lie within a radius of each other in the joint space
// (x1, y1, x2, y2). Correct matches of one surface move alike and so are close there; a wrong
// match lands far from its image-1 neighbours' partners in image 2.
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace varsfm {

struct NeighbourhoodGraph {
  std::vector<std::pair<int, int>> edges;  // (i, j) with i < j, sorted
};

// The radius is set from the data, so that a correspondence has about `mean_neighbours`
// neighbours in image 1 alone (r^2 = mean_neighbours x area / (pi n), area: the bounding box
// of x1): a fixed pixel radius would give a 3000-pixel photo a fifth of the neighbours of a
// 600-pixel one. A uniform grid of cells of that size finds the pairs; the result does not
// depend on the hash table's order.
NeighbourhoodGraph CorrespondenceNeighbourhood(const std::vector<Eigen::Vector2d>& x1,
                                               const std::vector<Eigen::Vector2d>& x2,
                                               double mean_neighbours);

}  // namespace varsfm
