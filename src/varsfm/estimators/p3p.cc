#include "varsfm/estimators/p3p.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include "varsfm/estimators/polynomial.h"

namespace varsfm {
namespace {

// The pairs (i, j) of the three constraints, in the order of DistanceConstraints' arrays.
constexpr int kFirst[3] = {0, 0, 1};
constexpr int kSecond[3] = {1, 2, 2};

int PairIndex(int i, int j) { return i + j - 1; }  // (0,1) -> 0, (0,2) -> 1, (1,2) -> 2

// lambda_i^2 + lambda_j^2 - 2 b_ij lambda_i lambda_j = a_ij for the three pairs.
struct DistanceConstraints {
  std::array<double, 3> a;  // squared distances between the world points
  std::array<double, 3> b;  // cosines of the angles between the bearings

  Eigen::Vector3d Residuals(const Eigen::Vector3d& l) const {
    Eigen::Vector3d r;
    for (int k = 0; k < 3; ++k) {
      const double li = l[kFirst[k]], lj = l[kSecond[k]];
      r[k] = li * li + lj * lj - 2 * b[k] * li * lj - a[k];
    }
    return r;
  }
  Eigen::Matrix3d Jacobian(const Eigen::Vector3d& l) const {
    Eigen::Matrix3d J = Eigen::Matrix3d::Zero();
    for (int k = 0; k < 3; ++k) {
      const int i = kFirst[k], j = kSecond[k];
      J(k, i) = 2 * (l[i] - b[k] * l[j]);
      J(k, j) = 2 * (l[j] - b[k] * l[i]);
    }
    return J;
  }
};

// Gauss-Newton on the three constraints, keeping only steps that lower the residual: the
// closed form loses digits where gamma or a quadratic is badly conditioned.
void PolishDepths(const DistanceConstraints& c, Eigen::Vector3d* lambda) {
  Eigen::Vector3d r = c.Residuals(*lambda);
  for (int iteration = 0; iteration < 5; ++iteration) {
    const Eigen::PartialPivLU<Eigen::Matrix3d> lu(c.Jacobian(*lambda));
    if (!(std::abs(lu.determinant()) > 0)) return;
    const Eigen::Vector3d next = *lambda - lu.solve(r);
    const Eigen::Vector3d r_next = c.Residuals(next);
    if (!(r_next.squaredNorm() < r.squaredNorm())) return;
    *lambda = next;
    r = r_next;
  }
}

double Det(const Eigen::Vector3d& c0, const Eigen::Vector3d& c1, const Eigen::Vector3d& c2) {
  return c0.dot(c1.cross(c2));
}

// Coefficients (c3, c2, c1, c0) of det(D1 + gamma D2), by the multilinearity of the
// determinant in the columns.
std::array<double, 4> PencilDeterminant(const Eigen::Matrix3d& D1, const Eigen::Matrix3d& D2) {
  const auto a0 = D1.col(0), a1 = D1.col(1), a2 = D1.col(2);
  const auto b0 = D2.col(0), b1 = D2.col(1), b2 = D2.col(2);
  return {Det(b0, b1, b2), Det(a0, b1, b2) + Det(b0, a1, b2) + Det(b0, b1, a2),
          Det(b0, a1, a2) + Det(a0, b1, a2) + Det(a0, a1, b2), Det(a0, a1, a2)};
}

// The degenerate member D0 of the pencil as the pair of planes through the origin it vanishes
// on: sigma_p (e_p . L)^2 + sigma_q (e_q . L)^2 = 0 with sigma_p sigma_q < 0 gives
// (e_p -+ s e_q) . L = 0, s = sqrt(-sigma_q / sigma_p). Of the cubic's real roots, the one
// whose two non-zero eigenvalues are largest against the matrix's norm is taken (the paper
// notes any real root serves; this one separates the planes best).
bool DegeneratePlanes(const Eigen::Matrix3d& D1, const Eigen::Matrix3d& D2,
                      std::array<Eigen::Vector3d, 2>* planes) {
  const std::array<double, 4> c = PencilDeterminant(D1, D2);
  std::vector<double> gammas;
  SolveCubicReal(c[0], c[1], c[2], c[3], &gammas);
  double best_quality = 0;
  for (const double gamma : gammas) {
    Eigen::Matrix3d D0 = D1 + gamma * D2;
    const double norm = D0.norm();
    if (!(norm > 0) || !std::isfinite(norm)) continue;
    D0 /= norm;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(D0);
    const Eigen::Vector3d& sigma = eigen.eigenvalues();
    int z = 0;
    for (int k = 1; k < 3; ++k)
      if (std::abs(sigma[k]) < std::abs(sigma[z])) z = k;
    const int p = (z + 1) % 3, q = (z + 2) % 3;
    if (!(sigma[p] * sigma[q] < 0)) continue;
    const double quality = std::min(std::abs(sigma[p]), std::abs(sigma[q]));
    if (!(quality > best_quality)) continue;
    best_quality = quality;
    const double s = std::sqrt(-sigma[q] / sigma[p]);
    (*planes)[0] = eigen.eigenvectors().col(p) - s * eigen.eigenvectors().col(q);
    (*planes)[1] = eigen.eigenvectors().col(p) + s * eigen.eigenvectors().col(q);
  }
  return best_quality > 0;
}

// The depths on the plane `normal` . L = 0 that also satisfy the constraints: the plane's
// largest coefficient's depth is eliminated, L = lambda_i (u + tau w) with tau = lambda_j /
// lambda_i, and tau is a root of the quadratic form D1 or D2 restricted to the plane (the one
// that does not vanish there: on the plane D1 = -gamma D2); the pair (i, j)'s constraint gives
// the scale.
void DepthsOnPlane(const Eigen::Vector3d& normal, const Eigen::Matrix3d& D1,
                   const Eigen::Matrix3d& D2, const DistanceConstraints& c,
                   std::vector<Eigen::Vector3d>* depths) {
  int k = 0;
  normal.cwiseAbs().maxCoeff(&k);
  const int i = k == 0 ? 1 : 0, j = k == 2 ? 1 : 2;
  Eigen::Vector3d u = Eigen::Vector3d::Unit(i), w = Eigen::Vector3d::Unit(j);
  u[k] = -normal[i] / normal[k];
  w[k] = -normal[j] / normal[k];
  const auto coefficients = [&](const Eigen::Matrix3d& D) {
    return Eigen::Vector3d(w.dot(D * w), 2 * u.dot(D * w), u.dot(D * u));
  };
  const Eigen::Vector3d q1 = coefficients(D1), q2 = coefficients(D2);
  const Eigen::Vector3d& q = q1.cwiseAbs().maxCoeff() > q2.cwiseAbs().maxCoeff() ? q1 : q2;
  std::vector<double> taus;
  SolveQuadraticReal(q[0], q[1], q[2], &taus);
  const int m = PairIndex(i, j);
  for (const double tau : taus) {
    if (!(tau > 0)) continue;
    const double denominator = 1 + tau * tau - 2 * c.b[m] * tau;
    if (!(denominator > 0)) continue;
    Eigen::Vector3d lambda = std::sqrt(c.a[m] / denominator) * (u + tau * w);
    if (!(lambda.minCoeff() > 0)) continue;
    PolishDepths(c, &lambda);
    if (lambda.minCoeff() > 0) depths->push_back(lambda);
  }
}

}  // namespace

int SolveP3P(const std::array<Eigen::Vector3d, 3>& bearings,
             const std::array<Eigen::Vector3d, 3>& points, std::vector<Rigid3d>* poses) {
  std::array<Eigen::Vector3d, 3> y;
  for (int k = 0; k < 3; ++k) {
    const double norm = bearings[k].norm();
    if (!(norm > 0) || !std::isfinite(norm)) return 0;
    y[k] = bearings[k] / norm;
  }
  DistanceConstraints c;
  for (int k = 0; k < 3; ++k) {
    c.a[k] = (points[kFirst[k]] - points[kSecond[k]]).squaredNorm();
    c.b[k] = y[kFirst[k]].dot(y[kSecond[k]]);
  }
  // The world triangle fixes the rotation through its two edges and their normal: collinear
  // (or coincident) points leave it free.
  const Eigen::Vector3d edge1 = points[0] - points[1], edge2 = points[0] - points[2];
  const Eigen::Vector3d normal = edge1.cross(edge2);
  if (!(normal.squaredNorm() > 1e-20 * c.a[0] * c.a[1])) return 0;

  // Lambda^T M_ij Lambda = a_ij, and two combinations that vanish at every solution.
  std::array<Eigen::Matrix3d, 3> M;
  for (int k = 0; k < 3; ++k) {
    const int i = kFirst[k], j = kSecond[k];
    M[k].setZero();
    M[k](i, i) = M[k](j, j) = 1;
    M[k](i, j) = M[k](j, i) = -c.b[k];
  }
  const Eigen::Matrix3d D1 = c.a[2] * M[0] - c.a[0] * M[2];
  const Eigen::Matrix3d D2 = c.a[2] * M[1] - c.a[1] * M[2];
  std::array<Eigen::Vector3d, 2> planes;
  if (!DegeneratePlanes(D1, D2, &planes)) return 0;
  std::vector<Eigen::Vector3d> depths;
  for (const Eigen::Vector3d& plane : planes) DepthsOnPlane(plane, D1, D2, c, &depths);

  // R maps the world triangle's frame (two edges, their normal) onto the camera triangle's.
  Eigen::Matrix3d world_frame;
  world_frame << edge1, edge2, normal;
  const Eigen::Matrix3d world_frame_inverse = world_frame.inverse();
  const Eigen::Vector3d world_centroid = (points[0] + points[1] + points[2]) / 3.0;
  int added = 0;
  for (const Eigen::Vector3d& lambda : depths) {
    std::array<Eigen::Vector3d, 3> Y;
    for (int k = 0; k < 3; ++k) Y[k] = lambda[k] * y[k];
    Eigen::Matrix3d camera_frame;
    camera_frame << Y[0] - Y[1], Y[0] - Y[2], (Y[0] - Y[1]).cross(Y[0] - Y[2]);
    Eigen::Quaterniond rotation(Eigen::Matrix3d(camera_frame * world_frame_inverse));
    rotation.normalize();
    const Eigen::Vector3d translation = (Y[0] + Y[1] + Y[2]) / 3.0 - rotation * world_centroid;
    if (!translation.allFinite() || !rotation.coeffs().allFinite()) continue;
    poses->emplace_back(rotation, translation);
    ++added;
  }
  return added;
}

}  // namespace varsfm
