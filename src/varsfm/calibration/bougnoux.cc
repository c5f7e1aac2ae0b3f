#include "varsfm/calibration/bougnoux.h"

#include <cmath>

#include "varsfm/geometry/fundamental.h"

namespace varsfm {
namespace {

// f1^2 of the formula in the header, evaluated in coordinates centred on the principal points
// and scaled by `s` (conditioning: F's entries then have comparable magnitudes).
double SquaredFocalOfFirstView(const Eigen::Matrix3d& F, const Eigen::Vector2d& pp1,
                               const Eigen::Vector2d& pp2, double s) {
  Eigen::Matrix3d T1, T2;  // pixel -> centred, scaled
  T1 << 1 / s, 0, -pp1.x() / s, 0, 1 / s, -pp1.y() / s, 0, 0, 1;
  T2 << 1 / s, 0, -pp2.x() / s, 0, 1 / s, -pp2.y() / s, 0, 0, 1;
  const Eigen::Matrix3d Fn = T2.transpose().inverse() * F * T1.inverse();
  Eigen::Vector3d e1, e2;
  Epipoles(Fn, &e1, &e2);
  const Eigen::Vector3d p(0, 0, 1);
  const Eigen::Matrix3d I = Eigen::Vector3d(1, 1, 0).asDiagonal();
  const Eigen::Matrix3d E2 = CrossProductMatrix(e2);
  const double numerator = -(p.transpose() * E2 * I * Fn * p).value() *
                           (p.transpose() * Fn.transpose() * p).value();
  const double denominator = (p.transpose() * E2 * I * Fn * I * Fn.transpose() * p).value();
  return numerator / denominator * s * s;
}

}  // namespace

std::pair<double, double> BougnouxSquaredFocalLengths(const Eigen::Matrix3d& F,
                                                      const Eigen::Vector2d& pp1,
                                                      const Eigen::Vector2d& pp2) {
  const double s = 0.5 * (pp1.norm() + pp2.norm()) + 1.0;
  return {SquaredFocalOfFirstView(F, pp1, pp2, s),
          SquaredFocalOfFirstView(F.transpose(), pp2, pp1, s)};
}

std::optional<std::pair<double, double>> BougnouxFocalLengths(const Eigen::Matrix3d& F,
                                                              const Eigen::Vector2d& pp1,
                                                              const Eigen::Vector2d& pp2) {
  const auto [f1_sq, f2_sq] = BougnouxSquaredFocalLengths(F, pp1, pp2);
  if (!(f1_sq > 0) || !(f2_sq > 0)) return std::nullopt;
  return std::make_pair(std::sqrt(f1_sq), std::sqrt(f2_sq));
}

double PrincipalPointEpipolarDistance(const Eigen::Matrix3d& F, const Eigen::Vector2d& pp1,
                                      const Eigen::Vector2d& pp2) {
  const Eigen::Vector3d line = F * pp1.homogeneous();
  return std::abs(line.dot(pp2.homogeneous())) / line.head<2>().norm();
}

}  // namespace varsfm
