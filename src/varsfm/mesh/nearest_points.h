#pragma once
// A point cloud in a k-d tree (Open3D's, nanoflann) for nearest-point distances over the whole
// cloud: its spacing, and how far a mesh's vertices lie from it (mesh_quality.h).
#include <memory>
#include <vector>

#include <Eigen/Core>

namespace open3d::geometry {
class KDTreeFlann;
}

namespace varsfm {

class NearestPoints {
 public:
  // Keeps a reference to `points`, which must outlive it.
  explicit NearestPoints(const std::vector<Eigen::Vector3d>& points);
  ~NearestPoints();
  NearestPoints(const NearestPoints&) = delete;
  NearestPoints& operator=(const NearestPoints&) = delete;

  const std::vector<Eigen::Vector3d>& points() const { return points_; }

  // For each query, the distance to its nearest point of the cloud (threads over the queries).
  std::vector<double> DistancesTo(const std::vector<Eigen::Vector3d>& queries) const;
  // For each point of the cloud, the distance to its nearest other point (0 for a duplicate).
  std::vector<double> NearestOtherDistances() const;

 private:
  // The distance to the k-th nearest point of each query (k = 1: the nearest).
  std::vector<double> KthDistances(const std::vector<Eigen::Vector3d>& queries, int k) const;

  const std::vector<Eigen::Vector3d>& points_;
  Eigen::MatrixXd data_;  // the tree indexes this copy in place (Open3D's KDTreeFlann keeps a view)
  std::unique_ptr<open3d::geometry::KDTreeFlann> tree_;
};

// Mean distance from each point to its nearest other point, over every point. Needs at least
// two points.
double AverageNearestSpacing(const NearestPoints& cloud);
double AverageNearestSpacing(const std::vector<Eigen::Vector3d>& points);

}  // namespace varsfm
