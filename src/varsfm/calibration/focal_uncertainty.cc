#include "varsfm/calibration/focal_uncertainty.h"

#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Dense>

#include "varsfm/ba/analytic_reprojection_cost.h"
#include "varsfm/geometry/fundamental.h"

namespace varsfm {
namespace {

// log f1, log f2, rotation of image 2 (3), its translation (2), then k1, k2 of each camera.
constexpr int kNumParams = 11;
constexpr int kNumWithoutDistortion = 7;
using ParamRow = Eigen::Matrix<double, 2, kNumParams>;

}  // namespace

std::optional<std::pair<double, double>> TwoViewLogFocalStdDev(const Reconstruction& rec,
                                                               image_t image_id1, image_t image_id2,
                                                               double sigma_px,
                                                               bool with_distortion) {
  const image_t ids[2] = {image_id1, image_id2};
  // The translation of image 2 moves on the sphere |t| = const: two tangent directions.
  const Eigen::Vector3d t2 = rec.image(image_id2).cam_from_world.translation;
  if (t2.norm() == 0.0) return std::nullopt;
  const Eigen::Vector3d t_dir = t2.normalized();
  Eigen::Vector3d any =
      std::abs(t_dir.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  Eigen::Matrix<double, 3, 2> t_basis;
  t_basis.col(0) = t_dir.cross(any).normalized();
  t_basis.col(1) = t_dir.cross(t_basis.col(0));

  Eigen::Matrix<double, kNumParams, kNumParams> S =
      Eigen::Matrix<double, kNumParams, kNumParams>::Zero();
  for (const auto& [point_id, point] : rec.points3D()) {
    Eigen::Matrix<double, kNumParams, kNumParams> A =
        Eigen::Matrix<double, kNumParams, kNumParams>::Zero();
    Eigen::Matrix<double, kNumParams, 3> B = Eigen::Matrix<double, kNumParams, 3>::Zero();
    Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
    int observations = 0;
    for (const TrackElement& el : point.track) {
      const int k = el.image_id == ids[0] ? 0 : el.image_id == ids[1] ? 1 : -1;
      if (k < 0) continue;
      const Image& image = rec.image(el.image_id);
      const Camera& camera = rec.camera(image.camera_id);
      const Rigid3d& pose = image.cam_from_world;
      const Eigen::Vector4d q = pose.rotation.coeffs();
      const double* blocks[] = {camera.params.data(), q.data(), pose.translation.data(),
                                point.xyz.data()};
      Eigen::Matrix<double, 2, Camera::kNumParams, Eigen::RowMajor> J_camera;
      Eigen::Matrix<double, 2, 4, Eigen::RowMajor> J_rotation;
      Eigen::Matrix<double, 2, 3, Eigen::RowMajor> J_translation, J_point;
      double* jacobians[] = {J_camera.data(), J_rotation.data(), J_translation.data(),
                             J_point.data()};
      double residuals[2];
      if (!AnalyticReprojectionCost(image.points2D[el.point2D_idx].xy)
               .Evaluate(blocks, residuals, jacobians))
        continue;
      ParamRow J = ParamRow::Zero();
      J.col(k) = J_camera.col(Camera::kFocal) * camera.focal();  // d/d(log f) = f d/df
      J.col(7 + 2 * k) = J_camera.col(Camera::kK1);
      J.col(8 + 2 * k) = J_camera.col(Camera::kK2);
      if (k == 1) {
        // p = R X + t; a rotation exp([d]x) R moves p by -[R X]x d, a translation by B t_basis.
        J.middleCols<3>(2) = J_translation * -CrossProductMatrix(pose.rotation * point.xyz);
        J.middleCols<2>(5) = J_translation * t_basis;
      }
      A += J.transpose() * J;
      B += J.transpose() * J_point;
      C += J_point.transpose() * J_point;
      ++observations;
    }
    if (observations < 2) continue;
    const Eigen::LDLT<Eigen::Matrix3d> C_ldlt(C);
    if (C_ldlt.info() != Eigen::Success || !C_ldlt.isPositive()) continue;
    S += A - B * C_ldlt.solve(B.transpose());
  }
  // Held distortion: the information of the other parameters is S's leading block (conditioning
  // on k1, k2); free distortion: the whole of S is inverted (marginalising them).
  const int n = with_distortion ? kNumParams : kNumWithoutDistortion;
  const Eigen::MatrixXd S_used = S.topLeftCorner(n, n);
  // A relative eigenvalue threshold: below it the valley is flat and f is undetermined.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(S_used);
  if (eig.info() != Eigen::Success ||
      eig.eigenvalues().minCoeff() <= 1e-12 * eig.eigenvalues().maxCoeff())
    return std::nullopt;
  const Eigen::MatrixXd covariance = sigma_px * sigma_px * eig.eigenvectors() *
                                     eig.eigenvalues().cwiseInverse().asDiagonal() *
                                     eig.eigenvectors().transpose();
  return std::make_pair(std::sqrt(covariance(0, 0)), std::sqrt(covariance(1, 1)));
}

}  // namespace varsfm
