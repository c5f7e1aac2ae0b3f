#include "varsfm/geometry/triangulation.h"

#include <cmath>
#include <limits>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/SVD>

namespace varsfm {
namespace {

// The homogeneous least-squares solution of A X = 0, dehomogenised.
template <typename Matrix>
bool SolveHomogeneous(const Matrix& A, Eigen::Vector3d* point) {
  const Eigen::JacobiSVD<Matrix> svd(A, Eigen::ComputeFullV);
  const Eigen::Vector4d X = svd.matrixV().col(3);
  if (std::abs(X[3]) <= 1e-12 * X.head<3>().norm() || !std::isfinite(X.sum())) return false;
  *point = X.head<3>() / X[3];
  return true;
}

// Adds the two DLT rows x (p3^T X) - p1^T X, y (p3^T X) - p2^T X of one view, scaled to unit norm.
template <typename Matrix>
void AddRows(const Matrix34d& P, const Eigen::Vector2d& x, int row, Matrix* A) {
  A->row(row) = x.x() * P.row(2) - P.row(0);
  A->row(row + 1) = x.y() * P.row(2) - P.row(1);
  for (int r = row; r < row + 2; ++r) {
    const double n = A->row(r).norm();
    if (n > 0) A->row(r) /= n;
  }
}

}  // namespace

bool TriangulatePoint(const Matrix34d& P1, const Matrix34d& P2, const Eigen::Vector2d& x1,
                      const Eigen::Vector2d& x2, Eigen::Vector3d* point) {
  Eigen::Matrix4d A;
  AddRows(P1, x1, 0, &A);
  AddRows(P2, x2, 2, &A);
  return SolveHomogeneous(A, point);
}

bool TriangulateMultiView(const std::vector<Matrix34d>& Ps, const std::vector<Eigen::Vector2d>& xs,
                          Eigen::Vector3d* point) {
  if (Ps.size() < 2 || Ps.size() != xs.size()) return false;
  Eigen::MatrixXd A(2 * Ps.size(), 4);
  for (size_t i = 0; i < Ps.size(); ++i) AddRows(Ps[i], xs[i], 2 * static_cast<int>(i), &A);
  return SolveHomogeneous(A, point);
}

double ReprojectionError(const Camera& camera, const Rigid3d& cam_from_world,
                         const Eigen::Vector2d& pixel, const Eigen::Vector3d& point) {
  const Eigen::Vector3d x = cam_from_world * point;
  if (x.z() <= 0) return std::numeric_limits<double>::infinity();
  return (camera.Project(x) - pixel).norm();
}

bool RefineTriangulatedPoint(const std::vector<Camera>& cameras,
                             const std::vector<Rigid3d>& cams_from_world,
                             const std::vector<Eigen::Vector2d>& pixels, Eigen::Vector3d* point,
                             int max_iterations) {
  const size_t n = cameras.size();
  if (n < 2 || cams_from_world.size() != n || pixels.size() != n) return false;
  std::vector<Eigen::Matrix3d> rotations(n);
  for (size_t i = 0; i < n; ++i) rotations[i] = cams_from_world[i].R();

  // Residuals and normal equations at X; false when X is behind a camera.
  const auto linearize = [&](const Eigen::Vector3d& X, Eigen::Matrix3d* JtJ, Eigen::Vector3d* Jtr,
                             double* cost) {
    JtJ->setZero();
    Jtr->setZero();
    *cost = 0;
    for (size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d xc = cams_from_world[i] * X;
      if (xc.z() <= 0) return false;
      const auto& p = cameras[i].params;
      const double iz = 1.0 / xc.z();
      const Eigen::Vector2d xn(xc.x() * iz, xc.y() * iz);
      const double r2 = xn.squaredNorm();
      const double k1 = p[Camera::kK1], k2 = p[Camera::kK2];
      const double d = 1 + r2 * (k1 + k2 * r2);
      const Eigen::Vector2d xd = d * xn;
      Eigen::Matrix2d A;  // the affine part of K acting on distorted coordinates
      A << p[Camera::kFocal], p[Camera::kSkew], 0, p[Camera::kAspect] * p[Camera::kFocal];
      const Eigen::Vector2d r =
          A * xd + Eigen::Vector2d(p[Camera::kU0], p[Camera::kV0]) - pixels[i];
      // Chain rule: d pixel/dX = A * d(xd)/d(xn) * d(xn)/d(xc) * R, with eq. (5)'s
      // d(xd)/d(xn) = d I + 2 d'(r2) xn xn^T.
      const Eigen::Matrix2d J_dist =
          d * Eigen::Matrix2d::Identity() + 2 * (k1 + 2 * k2 * r2) * xn * xn.transpose();
      Eigen::Matrix<double, 2, 3> J_proj;
      J_proj << iz, 0, -xn.x() * iz, 0, iz, -xn.y() * iz;
      const Eigen::Matrix<double, 2, 3> J = A * J_dist * J_proj * rotations[i];
      *JtJ += J.transpose() * J;
      *Jtr += J.transpose() * r;
      *cost += r.squaredNorm();
    }
    return true;
  };

  Eigen::Vector3d X = *point;
  Eigen::Matrix3d JtJ;
  Eigen::Vector3d Jtr;
  double cost;
  if (!linearize(X, &JtJ, &Jtr, &cost)) return false;
  double lambda = 1e-4;
  for (int iter = 0; iter < max_iterations; ++iter) {
    Eigen::Matrix3d H = JtJ;
    H.diagonal() *= 1.0 + lambda;
    const Eigen::Vector3d step = H.ldlt().solve(-Jtr);
    if (!std::isfinite(step.sum())) return false;
    const Eigen::Vector3d X_new = X + step;
    Eigen::Matrix3d JtJ_new;
    Eigen::Vector3d Jtr_new;
    double cost_new;
    if (linearize(X_new, &JtJ_new, &Jtr_new, &cost_new) && cost_new < cost) {
      const bool converged = cost - cost_new < 1e-12 * cost || step.norm() < 1e-12 * X.norm();
      X = X_new;
      JtJ = JtJ_new;
      Jtr = Jtr_new;
      cost = cost_new;
      lambda = std::max(lambda * 0.1, 1e-10);
      if (converged) break;
    } else {
      lambda *= 10;
      if (lambda > 1e8) break;
    }
  }
  *point = X;
  return true;
}

double TriangulationAngle(const Eigen::Vector3d& center1, const Eigen::Vector3d& center2,
                          const Eigen::Vector3d& point) {
  const Eigen::Vector3d a = point - center1;
  const Eigen::Vector3d b = point - center2;
  // atan2(|a x b|, a.b) stays accurate for the small angles that matter here, unlike acos.
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

bool HasPositiveDepth(const Rigid3d& cam_from_world, const Eigen::Vector3d& point) {
  return (cam_from_world * point).z() > std::numeric_limits<double>::epsilon();
}

double ProjectionDepth(const Matrix34d& P, const Eigen::Vector3d& point) {
  const double w = P.row(2).dot(point.homogeneous());
  const double det = P.leftCols<3>().determinant();
  return (det < 0 ? -w : w) / P.block<1, 3>(2, 0).norm();
}

}  // namespace varsfm
