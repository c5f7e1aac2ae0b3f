#include "varsfm/estimators/essential_5pt.h"

#include <array>
#include <cmath>
#include <complex>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>

#include "varsfm/estimators/null_vector.h"

namespace varsfm {
namespace {

// Polynomials of degree <= 3 in (x, y, z), stored densely over 20 monomials in graded reverse
// lexicographic order: first the ten cubics, then the ten monomials of degree <= 2, which are
// the normal set (quotient-ring basis) once every cubic is reduced by the ten constraints.
constexpr std::array<std::array<int, 3>, 20> kExponents = {{
    {3, 0, 0}, {2, 1, 0}, {2, 0, 1}, {1, 2, 0}, {1, 1, 1}, {1, 0, 2},
    {0, 3, 0}, {0, 2, 1}, {0, 1, 2}, {0, 0, 3},                        // cubics
    {2, 0, 0}, {1, 1, 0}, {1, 0, 1}, {0, 2, 0}, {0, 1, 1}, {0, 0, 2},  // quadratics
    {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, 0},                        // x, y, z, 1
}};
constexpr int kNumCubic = 10;
constexpr int kX = 16, kY = 17, kZ = 18, kOne = 19;  // positions in kExponents
constexpr int kLinearStart = 16, kQuadraticStart = 10;

using Poly = std::array<double, 20>;

// kProduct[i][j]: the position of monomial i times monomial j (-1 when degree > 3).
constexpr std::array<std::array<int, 20>, 20> MakeProductTable() {
  std::array<std::array<int, 20>, 20> table{};
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 20; ++j) {
      table[i][j] = -1;
      for (int k = 0; k < 20; ++k) {
        if (kExponents[k][0] == kExponents[i][0] + kExponents[j][0] &&
            kExponents[k][1] == kExponents[i][1] + kExponents[j][1] &&
            kExponents[k][2] == kExponents[i][2] + kExponents[j][2])
          table[i][j] = k;
      }
    }
  }
  return table;
}
constexpr auto kProduct = MakeProductTable();

// a * b where a has no terms before position a_start and b none before b_start (the caller
// guarantees the product has degree <= 3).
Poly Multiply(const Poly& a, int a_start, const Poly& b, int b_start) {
  Poly c{};
  for (int i = a_start; i < 20; ++i) {
    if (a[i] == 0) continue;
    for (int j = b_start; j < 20; ++j) c[kProduct[i][j]] += a[i] * b[j];
  }
  return c;
}

Poly Add(const Poly& a, const Poly& b, double scale_b = 1.0) {
  Poly c;
  for (int i = 0; i < 20; ++i) c[i] = a[i] + scale_b * b[i];
  return c;
}

}  // namespace

int Essential5pt(const std::vector<Eigen::Vector2d>& x1, const std::vector<Eigen::Vector2d>& x2,
                 std::vector<Eigen::Matrix3d>* models) {
  if (x1.size() < 5 || x2.size() < 5) return 0;
  // Null space of the five epipolar constraints q_i^T e = 0 (e = E row-major), from the full Q
  // of the QR decomposition of the 9x5 matrix of constraint vectors.
  Eigen::Matrix<double, 9, 5> At;
  for (int i = 0; i < 5; ++i) {
    const double u1 = x1[i].x(), v1 = x1[i].y(), u2 = x2[i].x(), v2 = x2[i].y();
    At.col(i) << u2 * u1, u2 * v1, u2, v2 * u1, v2 * v1, v2, u1, v1, 1;
  }
  const Eigen::Matrix<double, 9, 9> Q =
      Eigen::HouseholderQR<Eigen::Matrix<double, 9, 5>>(At).householderQ();
  const Eigen::Matrix<double, 9, 4> basis = Q.rightCols<4>();  // X, Y, Z, W

  // E as a 3x3 matrix of linear polynomials x X + y Y + z Z + W.
  std::array<std::array<Poly, 3>, 3> E;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      E[r][c] = Poly{};
      E[r][c][kX] = basis(3 * r + c, 0);
      E[r][c][kY] = basis(3 * r + c, 1);
      E[r][c][kZ] = basis(3 * r + c, 2);
      E[r][c][kOne] = basis(3 * r + c, 3);
    }
  }

  Eigen::Matrix<double, 10, 20> C;
  // det(E) = 0 (one cubic).
  const auto cofactor = [&](int r0, int c0, int r1, int c1) {
    return Add(Multiply(E[r0][c0], kLinearStart, E[r1][c1], kLinearStart),
               Multiply(E[r0][c1], kLinearStart, E[r1][c0], kLinearStart), -1.0);
  };
  Poly det = Multiply(cofactor(1, 1, 2, 2), kQuadraticStart, E[0][0], kLinearStart);
  det = Add(det, Multiply(cofactor(1, 0, 2, 2), kQuadraticStart, E[0][1], kLinearStart), -1.0);
  det = Add(det, Multiply(cofactor(1, 0, 2, 1), kQuadraticStart, E[0][2], kLinearStart));
  for (int k = 0; k < 20; ++k) C(0, k) = det[k];

  // 2 E E^T E - tr(E E^T) E = 0 (nine cubics, Nister eq. 4).
  std::array<std::array<Poly, 3>, 3> EEt;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      Poly sum{};
      for (int k = 0; k < 3; ++k)
        sum = Add(sum, Multiply(E[r][k], kLinearStart, E[c][k], kLinearStart));
      EEt[r][c] = sum;
    }
  }
  const Poly trace = Add(Add(EEt[0][0], EEt[1][1]), EEt[2][2]);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      Poly eq{};
      for (int k = 0; k < 3; ++k)
        eq = Add(eq, Multiply(EEt[r][k], kQuadraticStart, E[k][c], kLinearStart), 2.0);
      eq = Add(eq, Multiply(trace, kQuadraticStart, E[r][c], kLinearStart), -1.0);
      for (int k = 0; k < 20; ++k) C(1 + 3 * r + c, k) = eq[k];
    }
  }

  // Gauss-Jordan elimination: cubic_k = -B_k . b with b the ten monomials of degree <= 2.
  const Eigen::PartialPivLU<Eigen::Matrix<double, 10, 10>> lu(C.leftCols<kNumCubic>());
  const Eigen::Matrix<double, 10, 10> B = lu.solve(C.rightCols<10>());
  if (!std::isfinite(B.sum())) return 0;

  // Action matrix of multiplication by x on the normal set b = (x^2, xy, xz, y^2, yz, z^2,
  // x, y, z, 1): x b = M b modulo the ideal. x^2 -> x^3, xy -> x^2y, xz -> x^2z,
  // y^2 -> xy^2, yz -> xyz, z^2 -> xz^2 (cubics 0..5, reduced by B); x -> x^2, y -> xy,
  // z -> xz, 1 -> x (basis elements). At a solution, b is an eigenvector with eigenvalue x.
  Eigen::Matrix<double, 10, 10> M = Eigen::Matrix<double, 10, 10>::Zero();
  M.topRows<6>() = -B.topRows<6>();
  M(6, 0) = 1;
  M(7, 1) = 1;
  M(8, 2) = 1;
  M(9, 6) = 1;
  const Eigen::EigenSolver<Eigen::Matrix<double, 10, 10>> eig(M);
  if (eig.info() != Eigen::Success) return 0;

  // eigenvectors() returns a new matrix: keep it, so that its columns outlive the statement.
  const Eigen::Matrix<std::complex<double>, 10, 10> vectors = eig.eigenvectors();
  int added = 0;
  for (int k = 0; k < 10; ++k) {
    const std::complex<double> lambda = eig.eigenvalues()[k];
    if (std::abs(lambda.imag()) > 1e-8 * std::max(1.0, std::abs(lambda.real()))) continue;
    const auto v = vectors.col(k);
    const std::complex<double> w = v[9];  // the monomial 1
    if (std::abs(w) < 1e-14 * v.norm()) continue;
    const double x = (v[6] / w).real(), y = (v[7] / w).real(), z = (v[8] / w).real();
    const Eigen::Matrix<double, 9, 1> e =
        x * basis.col(0) + y * basis.col(1) + z * basis.col(2) + basis.col(3);
    Eigen::Matrix3d Em = MatrixFromRowMajor(e);
    if (!ScaleToUnitNorm(&Em)) continue;
    models->push_back(Em);
    ++added;
  }
  return added;
}

}  // namespace varsfm
