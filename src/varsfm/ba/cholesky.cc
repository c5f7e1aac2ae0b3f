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
  UseNestedDissection(true);
}

// The fill-reducing ordering. CHOLMOD's default tries AMD and turns to METIS's nested dissection
// only when AMD's fill passes a threshold; the reduced camera system of a large model (a camera
// co-visibility graph) is ordered better by METIS well below it (docs/measurements.md, "Cholesky
// factorisations"). A CHOLMOD built without METIS refuses the method; then its default applies.
void SparseCholesky::UseNestedDissection(bool metis) {
  cholmod_common& common = llt_.cholmod();
  if (metis) {
    common.nmethods = 1;
    common.method[0].ordering = CHOLMOD_METIS;
  } else {
    common.nmethods = 0;  // CHOLMOD's default: AMD, and METIS when AMD's fill is large
  }
}

void SparseCholesky::AnalyzePattern(const Eigen::SparseMatrix<double>& upper) {
  llt_.analyzePattern(upper);
  if (llt_.cholmod().status != CHOLMOD_OK && llt_.cholmod().nmethods == 1) {
    UseNestedDissection(false);
    llt_.analyzePattern(upper);
  }
}

bool SparseCholesky::Factorize(const Eigen::SparseMatrix<double>& upper) {
  llt_.factorize(upper);
  return llt_.info() == Eigen::Success;
}

Eigen::VectorXd SparseCholesky::Solve(const Eigen::VectorXd& b) const { return llt_.solve(b); }

}  // namespace varsfm
