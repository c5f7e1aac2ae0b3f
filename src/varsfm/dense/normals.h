#pragma once
// Normals of a dense point cloud: the smallest principal axis of the k nearest neighbours
// (a uniform grid finds them), oriented towards a camera that sees the point.
#include <vector>

#include <Eigen/Core>

namespace varsfm {

// `spacing`: the typical distance between neighbouring points (e.g. a pixel's footprint); the
// grid cell is max(2, sqrt(k)) times that, shrunk where the cloud is denser (overlapping pairs)
// until a cell holds about k / 2 points, and the k nearest are searched in the 27 cells around
// a point. A point with fewer than 3 neighbours there gets the direction to its camera. Runs in
// parallel (TBB); deterministic.
std::vector<Eigen::Vector3d> EstimateNormals(const std::vector<Eigen::Vector3d>& points,
                                             const std::vector<Eigen::Vector3d>& view_centers,
                                             int k, double spacing);

}  // namespace varsfm
