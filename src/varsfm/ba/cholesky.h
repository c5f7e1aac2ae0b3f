#pragma once
// The Cholesky solves of the native bundle adjuster's reduced camera system
// (reduced_camera_system.cc), on the system BLAS (scripts/install_deps.sh makes it OpenBLAS, whose
// kernels are chosen for the CPU at run time; serial, so the results are reproducible).
//
// Measured on the 2-core development machine (AMD EPYC, 2026-12-01; a random SPD matrix, and a
// banded one of 9-column blocks each coupled with its 60 successors, as a street sequence's):
//   dense, 958 / 1345 / 2695 columns: Eigen's LLT 0.034 / 0.152 / 1.149 s, LAPACK's dpotrf
//   0.012 / 0.042 / 0.268 s; at 300 columns Eigen's 0.002 s against 0.004 s;
//   banded, 2700 / 9000 columns: Eigen's SimplicialLLT 0.53 / 1.91 s a factorisation, CHOLMOD's
//   supernodal one 0.11 / 0.72 s (the same solution to 1e-16).
#include <Eigen/CholmodSupport>
#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace varsfm {

// Solves S x = b for a symmetric positive definite S given by its upper triangle (which its
// Cholesky factor overwrites). LAPACK's dpotrf/dpotrs from 512 columns, Eigen's LLT below (where
// the call costs more than the kernels save). False when S is not positive definite.
bool SolveDenseCholesky(Eigen::MatrixXd* upper, const Eigen::VectorXd& b, Eigen::VectorXd* x);

// CHOLMOD's supernodal LLT of a sparse SPD matrix given by its upper triangle: analyse the
// pattern once, factorise at every step.
class SparseCholesky {
 public:
  SparseCholesky();
  void AnalyzePattern(const Eigen::SparseMatrix<double>& upper);
  // False when the matrix is not positive definite.
  bool Factorize(const Eigen::SparseMatrix<double>& upper);
  Eigen::VectorXd Solve(const Eigen::VectorXd& b) const;

 private:
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper> llt_;
};

}  // namespace varsfm
