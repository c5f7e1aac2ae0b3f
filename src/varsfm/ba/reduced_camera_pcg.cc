#include <cmath>
#include <vector>

#include <Eigen/Cholesky>

#include "varsfm/ba/schur_system.h"
#include "varsfm/util/timer.h"

// The reduced camera system solved by preconditioned conjugate gradients (Hestenes & Stiefel
// 1952; Nocedal & Wright, "Numerical Optimization", 2nd ed., Algorithm 5.3) instead of a
// Cholesky factorisation, for a large system whose camera graph is dense: on a set that
// densifies (each image sharing points with a growing share of the others) the sparse
// factorisation's fill approaches the dense n^3 / 3, while a product with the explicit reduced
// system costs its blocks. As COLMAP's choice beyond a size and Ceres' ITERATIVE_SCHUR, but on
// the explicit reduced system (its blocks are built anyway) with the block-Jacobi
// preconditioner, the inverse of each image's diagonal block (Agarwal et al., "Bundle
// adjustment in the large", ECCV 2010, sec. 4.3). One thread, sums in block order: the same
// result with any number of threads.

namespace varsfm {

// y = A x for the Jacobi-scaled reduced system A = L S L (S in work_, upper block triangle;
// `scale` the diagonal of L): each stored block (a, b), a < b, also acts as its transpose.
void SchurSystem::MultiplyScaledReduced(const Eigen::VectorXd& scale, const Eigen::VectorXd& x,
                                        Eigen::VectorXd* y) const {
  const Eigen::VectorXd z = scale.cwiseProduct(x);
  Eigen::VectorXd w = Eigen::VectorXd::Zero(num_columns_);
  for (int a = 0; a < num_column_blocks_; ++a) {
    const int ta = blocks_[a].tangent, ca = blocks_[a].column;
    for (int k = pair_begin_[a]; k < pair_begin_[a + 1]; ++k) {
      const int b = pair_block_[k];
      const int tb = blocks_[b].tangent, cb = blocks_[b].column;
      const double* block = &work_[pair_offset_[k]];  // (j, c) at c * ta + j
      if (b == a) {                                   // the diagonal block: its upper triangle
        for (int c = 0; c < ta; ++c) {
          w[ca + c] += block[c * ta + c] * z[ca + c];
          for (int j = 0; j < c; ++j) {
            w[ca + j] += block[c * ta + j] * z[ca + c];
            w[ca + c] += block[c * ta + j] * z[ca + j];
          }
        }
        continue;
      }
      for (int c = 0; c < tb; ++c) {
        double to_b = 0.0;
        for (int j = 0; j < ta; ++j) {
          w[ca + j] += block[c * ta + j] * z[cb + c];
          to_b += block[c * ta + j] * z[ca + j];
        }
        w[cb + c] += to_b;
      }
    }
  }
  *y = scale.cwiseProduct(w);
}

// Solves A y = b (A the scaled reduced system) to |A y - b| <= tolerance |b|; the residual
// A y - b stays in reduced_residual_ (the trust region's model needs it: an inexact step's
// model decrease, schur_step.cc). False when a diagonal block or a curvature is not positive.
bool SchurSystem::SolveScaledReducedIteratively(const Eigen::VectorXd& scale,
                                                const Eigen::VectorXd& b, Eigen::VectorXd* y) {
  // The preconditioner: the Cholesky factor of each diagonal block of A.
  std::vector<Eigen::LLT<Eigen::MatrixXd>> inverse(num_column_blocks_);
  for (int a = 0; a < num_column_blocks_; ++a) {
    const int ta = blocks_[a].tangent, ca = blocks_[a].column;
    const double* block = &work_[pair_offset_[pair_begin_[a]]];
    Eigen::MatrixXd m(ta, ta);
    for (int c = 0; c < ta; ++c)
      for (int j = 0; j <= c; ++j)
        m(j, c) = m(c, j) = block[c * ta + j] * scale[ca + j] * scale[ca + c];
    inverse[a].compute(m);
    if (inverse[a].info() != Eigen::Success) return false;
  }
  const auto precondition = [&](const Eigen::VectorXd& r, Eigen::VectorXd* z) {
    z->resize(num_columns_);
    for (int a = 0; a < num_column_blocks_; ++a) {
      const int ta = blocks_[a].tangent, ca = blocks_[a].column;
      z->segment(ca, ta) = inverse[a].solve(r.segment(ca, ta));
    }
  };
  y->setZero(num_columns_);
  Eigen::VectorXd r = -b;  // A y - b at y = 0
  Eigen::VectorXd z, p, q;
  precondition(r, &z);
  p = -z;
  double rz = r.dot(z);
  const double target = iterative_tolerance_ * b.norm();
  int k = 0;
  for (; k < iterative_max_iterations_ && r.norm() > target; ++k) {
    MultiplyScaledReduced(scale, p, &q);
    const double curvature = p.dot(q);
    if (!(curvature > 0.0)) return false;
    const double alpha = rz / curvature;
    *y += alpha * p;
    r += alpha * q;
    precondition(r, &z);
    const double rz_next = r.dot(z);
    p = -z + (rz_next / rz) * p;
    rz = rz_next;
  }
  cg_iterations_ += k;
  reduced_residual_ = r;
  return y->allFinite();
}

}  // namespace varsfm
