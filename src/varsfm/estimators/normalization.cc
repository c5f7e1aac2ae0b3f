#include "varsfm/estimators/normalization.h"

#include <cmath>

namespace varsfm {
namespace {

template <int D>
void Normalize(const std::vector<Eigen::Matrix<double, D, 1>>& points,
               std::vector<Eigen::Matrix<double, D, 1>>* normalized,
               Eigen::Matrix<double, D + 1, D + 1>* T) {
  using Vec = Eigen::Matrix<double, D, 1>;
  Vec centroid = Vec::Zero();
  for (const Vec& p : points) centroid += p;
  centroid /= static_cast<double>(std::max<size_t>(points.size(), 1));
  double mean_dist = 0;
  for (const Vec& p : points) mean_dist += (p - centroid).norm();
  mean_dist /= static_cast<double>(std::max<size_t>(points.size(), 1));
  const double scale = mean_dist > 0 ? std::sqrt(static_cast<double>(D)) / mean_dist : 1.0;
  T->setIdentity();
  T->template topLeftCorner<D, D>() *= scale;
  T->template topRightCorner<D, 1>() = -scale * centroid;
  normalized->resize(points.size());
  for (size_t i = 0; i < points.size(); ++i) (*normalized)[i] = scale * (points[i] - centroid);
}

}  // namespace

void NormalizePoints2D(const std::vector<Eigen::Vector2d>& points,
                       std::vector<Eigen::Vector2d>* normalized, Eigen::Matrix3d* T) {
  Normalize<2>(points, normalized, T);
}

void NormalizePoints3D(const std::vector<Eigen::Vector3d>& points,
                       std::vector<Eigen::Vector3d>* normalized, Eigen::Matrix4d* T) {
  Normalize<3>(points, normalized, T);
}

NormalizedCorrespondences NormalizeCorrespondences(const std::vector<Eigen::Vector2d>& x1,
                                                   const std::vector<Eigen::Vector2d>& x2) {
  NormalizedCorrespondences n;
  NormalizePoints2D(x1, &n.x1, &n.T1);
  NormalizePoints2D(x2, &n.x2, &n.T2);
  return n;
}

}  // namespace varsfm
