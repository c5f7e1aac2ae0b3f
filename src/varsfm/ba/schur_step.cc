#include "varsfm/ba/schur_system.h"

#include <algorithm>
#include <cmath>
#include <vector>

// The Schur system's steps: x [+] delta on each block's manifold and back, and the terms of
// Powell's dogleg (Nocedal & Wright, "Numerical Optimization", 2nd ed., sec. 4.1) over the
// Gauss-Newton step and the Jacobi-scaled gradient.

namespace varsfm {

bool SchurSystem::Step() {
  backup_.resize(num_parameters_);
  double* saved = backup_.data();
  std::vector<double> moved;
  for (const Block& b : blocks_) {
    std::copy_n(b.x, b.size, saved);
    const double* delta = b.column >= 0 ? delta_c_.data() + b.column : delta_p_[b.point].data();
    if (b.manifold) {
      moved.resize(b.size);
      if (!b.manifold->Plus(saved, delta, moved.data())) return Restore(), false;
      std::copy(moved.begin(), moved.end(), b.x);
    } else {
      for (int i = 0; i < b.size; ++i) b.x[i] = saved[i] + delta[i];
    }
    saved += b.size;
  }
  return true;
}

void SchurSystem::Restore() {
  const double* saved = backup_.data();
  for (const Block& b : blocks_) {
    std::copy_n(saved, b.size, b.x);
    saved += b.size;
  }
}

double SchurSystem::ParameterNorm() const {
  double sum = 0.0;
  for (const Block& b : blocks_)
    for (int i = 0; i < b.size; ++i) sum += b.x[i] * b.x[i];
  return std::sqrt(sum);
}

SchurSystem::DoglegTerms SchurSystem::KeepGaussNewtonStep(double mu) {
  DoglegTerms t;
  t.mu = mu;
  t.g_p = step_g_delta_;
  t.p_D_p = step_dDd_;
  gn_c_ = delta_c_;
  gn_p_ = delta_p_;
  u_c_.resize(num_columns_);
  for (int a = 0; a < num_column_blocks_; ++a) {
    const int ta = blocks_[a].tangent, col = blocks_[a].column;
    const double* d = &s_blocks_[pair_offset_[pair_begin_[a]]];
    for (int i = 0; i < ta; ++i) u_c_[col + i] = g_c_[col + i] / ClampDiagonal(d[i * ta + i]);
  }
  t.g_u = g_c_.dot(u_c_);
  if (iterative_) {
    t.p_rho = delta_c_.dot(reduced_residual_);
    t.u_rho = u_c_.dot(reduced_residual_);
  }
  u_p_.resize(num_points_);
  for (int p = 0; p < num_points_; ++p) {
    for (int i = 0; i < 3; ++i) u_p_[p][i] = g_p_[p][i] / ClampDiagonal(v_[p](i, i));
    t.g_u += g_p_[p].dot(u_p_[p]);
  }
  // u^T H u over H's blocks: S (upper block triangle, off-diagonal blocks twice), the
  // couplings W (twice) and the points' V.
  double uhu = 0.0;
  for (int a = 0; a < num_column_blocks_; ++a) {
    const int ta = blocks_[a].tangent;
    const double* ua = u_c_.data() + blocks_[a].column;
    for (int pair = pair_begin_[a]; pair < pair_begin_[a + 1]; ++pair) {
      const int b = pair_block_[pair];
      const int tb = blocks_[b].tangent;
      const double* ub = u_c_.data() + blocks_[b].column;
      const double* block = &s_blocks_[pair_offset_[pair]];  // (j, c) at c * ta + j
      double sum = 0.0;
      for (int c = 0; c < tb; ++c) {
        double col = 0.0;
        for (int j = 0; j < ta; ++j) col += ua[j] * block[c * ta + j];
        sum += col * ub[c];
      }
      uhu += b == a ? sum : 2.0 * sum;
    }
  }
  for (int p = 0; p < num_points_; ++p) {
    const Eigen::Vector3d& up = u_p_[p];
    uhu += up.dot(v_[p] * up);
    for (int a = point_couplings_begin_[p]; a < point_couplings_begin_[p + 1]; ++a) {
      const Block& ba = blocks_[couplings_[a].block];
      const double* W = &w_[couplings_[a].offset];  // column-major tangent x 3
      const double* ua = u_c_.data() + ba.column;
      for (int c = 0; c < 3; ++c) {
        double col = 0.0;
        for (int j = 0; j < ba.tangent; ++j) col += ua[j] * W[c * ba.tangent + j];
        uhu += 2.0 * col * up[c];
      }
    }
  }
  t.u_H_u = uhu;
  return t;
}

double SchurSystem::SetDoglegStep(double a, double b) {
  delta_c_ = a * gn_c_ + b * u_c_;
  double norm2 = delta_c_.squaredNorm();
  for (int p = 0; p < num_points_; ++p) {
    delta_p_[p] = a * gn_p_[p] + b * u_p_[p];
    norm2 += delta_p_[p].squaredNorm();
  }
  return std::sqrt(norm2);
}

}  // namespace varsfm
