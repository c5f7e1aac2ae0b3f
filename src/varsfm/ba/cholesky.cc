#include "varsfm/ba/cholesky.h"

#include <Eigen/Cholesky>

extern "C" {
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info);
void dpotrs_(const char* uplo, const int* n, const int* nrhs, const double* a, const int* lda,
             double* b, const int* ldb, int* info);
}

namespace varsfm {

bool SolveDenseCholesky(Eigen::MatrixXd* upper, const Eigen::VectorXd& b, Eigen::VectorXd* x) {
  const int n = static_cast<int>(upper->rows());
  if (n < 512) {
    const Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>, Eigen::Upper> llt(*upper);
    if (llt.info() != Eigen::Success) return false;
    *x = llt.solve(b);
    return true;
  }
  int info = 0;
  dpotrf_("U", &n, upper->data(), &n, &info);
  if (info != 0) return false;
  *x = b;
  const int nrhs = 1;
  dpotrs_("U", &n, &nrhs, upper->data(), &n, x->data(), &n, &info);
  return info == 0;
}

SparseCholesky::SparseCholesky() {
  llt_.cholmod().print = 0;  // a matrix that is not positive definite is an answer, not news
}

void SparseCholesky::AnalyzePattern(const Eigen::SparseMatrix<double>& upper) {
  llt_.analyzePattern(upper);
}

bool SparseCholesky::Factorize(const Eigen::SparseMatrix<double>& upper) {
  llt_.factorize(upper);
  return llt_.info() == Eigen::Success;
}

Eigen::VectorXd SparseCholesky::Solve(const Eigen::VectorXd& b) const { return llt_.solve(b); }

}  // namespace varsfm
