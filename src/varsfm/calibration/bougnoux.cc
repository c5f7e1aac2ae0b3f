#include "varsfm/calibration/bougnoux.h"

#include <cmath>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "varsfm/geometry/fundamental.h"

namespace varsfm {
namespace {

// Relative gap of the two largest singular values of K2^T F K1, zero for an essential matrix.
double EssentialCost(const Eigen::Matrix3d& F, const Eigen::Vector2d& pp1,
                     const Eigen::Vector2d& pp2, double f) {
  Eigen::Matrix3d K1, K2;
  K1 << f, 0, pp1.x(), 0, f, pp1.y(), 0, 0, 1;
  K2 << f, 0, pp2.x(), 0, f, pp2.y(), 0, 0, 1;
  const Eigen::Vector3d s =
      Eigen::JacobiSVD<Eigen::Matrix3d>(K2.transpose() * F * K1).singularValues();
  return s(0) > 0 ? (s(0) - s(1)) / s(0) : 1.0;
}

}  // namespace

std::optional<std::pair<double, double>> BougnouxFocalLengths(const Eigen::Matrix3d& F,
                                                              const Eigen::Vector2d& pp1,
                                                              const Eigen::Vector2d& pp2) {
  // Epipoles: F e1 = 0, F^T e2 = 0.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d e1 = svd.matrixV().col(2), e2 = svd.matrixU().col(2);
  const Eigen::Vector3d p1 = pp1.homogeneous(), p2 = pp2.homogeneous();
  const Eigen::Matrix3d I = Eigen::Vector3d(1, 1, 0).asDiagonal();
  // Bougnoux's formulas (also Hartley & Zisserman, 2nd ed., section 19.x; OpenCV-free):
  //   f1^2 = -(p2^T [e2]x I F p1)(p1^T F^T p2) / (p2^T [e2]x I F I F^T p2)
  //   f2^2 = -(p1^T [e1]x I F^T p2)(p2^T F p1) / (p1^T [e1]x I F^T I F p1)
  // Both are proportional to p2^T F p1, which vanishes when the optical axes meet.
  const double den1 = p2.dot(CrossProductMatrix(e2) * I * F * I * F.transpose() * p2);
  const double den2 = p1.dot(CrossProductMatrix(e1) * I * F.transpose() * I * F * p1);
  if (den1 == 0.0 || den2 == 0.0) return std::nullopt;
  const double f1_sq =
      -p2.dot(CrossProductMatrix(e2) * I * F * p1) * p1.dot(F.transpose() * p2) / den1;
  const double f2_sq =
      -p1.dot(CrossProductMatrix(e1) * I * F.transpose() * p2) * p2.dot(F * p1) / den2;
  if (!(f1_sq > 0.0) || !(f2_sq > 0.0)) return std::nullopt;
  return std::make_pair(std::sqrt(f1_sq), std::sqrt(f2_sq));
}

std::optional<double> EqualFocalLength(const Eigen::Matrix3d& F, const Eigen::Vector2d& pp1,
                                       const Eigen::Vector2d& pp2, double min_focal,
                                       double max_focal, double max_cost) {
  // Coarse scan in log f (the cost can have several local minima), then golden section.
  constexpr int kSteps = 200;
  const double lo = std::log(min_focal), hi = std::log(max_focal);
  int best = 0;
  double best_cost = 2.0;
  for (int i = 0; i <= kSteps; ++i) {
    const double c = EssentialCost(F, pp1, pp2, std::exp(lo + (hi - lo) * i / kSteps));
    if (c < best_cost) best_cost = c, best = i;
  }
  double a = lo + (hi - lo) * std::max(0, best - 1) / kSteps;
  double b = lo + (hi - lo) * std::min(kSteps, best + 1) / kSteps;
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  for (int it = 0; it < 60; ++it) {
    const double x1 = b - g * (b - a), x2 = a + g * (b - a);
    if (EssentialCost(F, pp1, pp2, std::exp(x1)) < EssentialCost(F, pp1, pp2, std::exp(x2)))
      b = x2;
    else
      a = x1;
  }
  const double f = std::exp(0.5 * (a + b));
  if (EssentialCost(F, pp1, pp2, f) > max_cost) return std::nullopt;
  return f;
}

}  // namespace varsfm
