#pragma once
// The Cholesky solves of the native bundle adjuster's reduced camera system
// (reduced_camera_system.cc), on the system BLAS (scripts/install_deps.sh makes it OpenBLAS, whose
// kernels are chosen for the CPU at run time; serial, so the results are reproducible).
// LAPACK's dense and CHOLMOD's supernodal factorisations are several times faster than Eigen's
// LLT and SimplicialLLT at the sizes the mapper meets (docs/measurements.md).
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
  void UseNestedDissection(bool metis);

  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper> llt_;
};

}  // namespace varsfm
