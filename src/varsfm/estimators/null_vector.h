#pragma once
// The pieces the linear (DLT-style) solvers share: the least-squares null vector of a design
// matrix A from its normal matrix A^T A (H&Z section A5.3: the unit x minimising |A x| is the
// eigenvector of A^T A with the smallest eigenvalue), and the scaling of a 3x3 solution to unit
// Frobenius norm. Accumulating the small N x N A^T A row by row keeps the cost linear in the
// number of correspondences; the Hartley normalisation (normalization.h) keeps it well
// conditioned.
#include <cmath>
#include <cstddef>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

namespace varsfm {

// AtA: the lower triangle of A^T A (as rankUpdate on selfadjointView<Eigen::Lower>() leaves it).
// False when the eigen-decomposition fails.
template <int N>
bool SmallestEigenvector(const Eigen::Matrix<double, N, N>& AtA, Eigen::Matrix<double, N, 1>* x) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eig(
      AtA.template selfadjointView<Eigen::Lower>());
  if (eig.info() != Eigen::Success) return false;
  *x = eig.eigenvectors().col(0);
  return true;
}

// The null vector of the design matrix A whose rows `add_rows(i, add)` hands to `add`, one call
// per row, for each correspondence i < count: A^T A accumulated row by row (the lower triangle),
// then SmallestEigenvector. The linear solvers (F8, H4, DLT6) differ only in their rows.
template <int N, typename AddRows>
bool NullVectorOfRows(size_t count, const AddRows& add_rows, Eigen::Matrix<double, N, 1>* x) {
  Eigen::Matrix<double, N, N> AtA = Eigen::Matrix<double, N, N>::Zero();
  // The lower triangle, element by element: the same sums in the same order as Eigen's
  // selfadjointView().rankUpdate(row), without its run-time dispatch per row.
  const auto add = [&AtA](const Eigen::Matrix<double, N, 1>& row) {
    for (int c = 0; c < N; ++c)
      for (int r = c; r < N; ++r) AtA(r, c) += row[r] * row[c];
  };
  for (size_t i = 0; i < count; ++i) add_rows(i, add);
  return SmallestEigenvector(AtA, x);
}

// The 3x3 matrix whose rows are h[0..2], h[3..5], h[6..8].
inline Eigen::Matrix3d MatrixFromRowMajor(const Eigen::Matrix<double, 9, 1>& h) {
  return Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(h.data());
}

// M / |M|_F; false (M unchanged) when the norm is 0 or not finite, a degenerate solution.
inline bool ScaleToUnitNorm(Eigen::Matrix3d* M) {
  const double norm = M->norm();
  if (!(norm > 0) || !std::isfinite(norm)) return false;
  *M /= norm;
  return true;
}

}  // namespace varsfm
