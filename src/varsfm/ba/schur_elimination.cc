#include "varsfm/ba/schur_system.h"

#include <algorithm>
#include <cmath>
#include <cstring>

// The elimination of the points (Triggs et al., "Bundle adjustment - a modern synthesis", 2000,
// sec. 6.1): each point's damped V^-1 and Schur terms T = W V^-1, the reduced system
// S + mu D - sum_p T_p W_p^T with its right-hand side -g_c + sum_p T_p g_p, and, once the reduced
// system is solved (reduced_camera_system.cc), the points' steps by back-substitution.

namespace varsfm {
namespace {

using Matrix3 = Eigen::Matrix3d;

// Four doubles as one value (GCC's vector extensions): a register of the x86-64-v3 clone's AVX2,
// two SSE2 registers of the baseline one. Written out because the compiler left the loop below
// scalar (the 27 entries of T spilled to the stack), and it is the solver's innermost loop.
// (-Wpsabi: the baseline clone passes them differently; they never cross a call, all inline.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
typedef double Double4 __attribute__((vector_size(32)));

inline Double4 Load4(const double* p) {
  Double4 v;
  std::memcpy(&v, p, sizeof(v));
  return v;
}

inline void Store4(const Double4& v, double* p) { std::memcpy(p, &v, sizeof(v)); }

// out -= T W^T for T, W column-major 9 x 3 and out column-major 9 x 9 (a pair of image blocks
// in the Schur complement, the solver's innermost loop): T's columns stay in registers (rows
// 0-3 and 4-7 as vectors, row 8 apart), each column of out takes three broadcasts of W.
inline void SubtractSchurTerm9(const double* __restrict T, const double* __restrict W,
                               double* __restrict out) {
  const Double4 t0a = Load4(T), t0b = Load4(T + 4);
  const Double4 t1a = Load4(T + 9), t1b = Load4(T + 13);
  const Double4 t2a = Load4(T + 18), t2b = Load4(T + 22);
  const double t08 = T[8], t18 = T[17], t28 = T[26];
  for (int c = 0; c < 9; ++c) {
    const double w0 = W[c], w1 = W[9 + c], w2 = W[18 + c];
    double* o = out + c * 9;
    Store4(Load4(o) - (t0a * w0 + t1a * w1 + t2a * w2), o);
    Store4(Load4(o + 4) - (t0b * w0 + t1b * w1 + t2b * w2), o + 4);
    o[8] -= t08 * w0 + t18 * w1 + t28 * w2;
  }
}
#pragma GCC diagnostic pop

// T = W V^-1 of one coupling (column-major tangent x 3, as W).
inline void SchurTerm(const double* __restrict W, const Eigen::Matrix3d& vi, int ta,
                      double* __restrict T) {
  for (int c = 0; c < 3; ++c)
    for (int j = 0; j < ta; ++j)
      T[c * ta + j] = W[j] * vi(0, c) + W[ta + j] * vi(1, c) + W[2 * ta + j] * vi(2, c);
}

}  // namespace

bool SchurSystem::SolveStep(double mu, double* model_decrease, double* step_norm) {
  // V^-1 and T = W V^-1 of every point, then each part's rows of the reduced system and its
  // right-hand side: S + mu D - sum_p T_p W_p^T and -g_c + sum_p T_p g_p.
  runner_.Run([&](int k) { part_ok_[k] = InvertPoints(k, mu); });
  if (!AllPartsOk()) return false;
  work_.resize(s_blocks_.size());
  rhs_.resize(num_columns_);
  runner_.Run([&](int k) { EliminatePoints(k, mu); });
  delta_c_.resize(num_columns_);
  double dDd = 0.0;
  if (num_columns_ > 0) {
    if (!SolveReducedSystem()) return false;
    for (int a = 0; a < num_column_blocks_; ++a) {
      const int ta = blocks_[a].tangent;
      const double* d = &s_blocks_[pair_offset_[pair_begin_[a]]];
      for (int i = 0; i < ta; ++i) {
        const double x = delta_c_[blocks_[a].column + i];
        dDd += ClampDiagonal(d[i * ta + i]) * x * x;
      }
    }
  }
  runner_.Run([&](int k) { part_ok_[k] = BackSubstitute(k); });
  if (!AllPartsOk()) return false;
  double g_delta = g_c_.dot(delta_c_);
  double norm2 = delta_c_.squaredNorm();
  for (int p = 0; p < num_points_; ++p) {  // in point order, whatever the parts
    g_delta += point_g_delta_[p];
    dDd += point_dDd_[p];
    norm2 += delta_p_[p].squaredNorm();
  }
  *model_decrease = -0.5 * g_delta + 0.5 * mu * dDd;
  // An inexact solve leaves rho_c = S delta_c - rhs: the model decrease -g.delta -
  // 1/2 delta^T H delta is then the above minus 1/2 delta_c . rho_c.
  if (iterative_) *model_decrease -= 0.5 * delta_c_.dot(reduced_residual_);
  *step_norm = std::sqrt(norm2);
  step_g_delta_ = g_delta;
  step_dDd_ = dDd;
  return true;
}

// Part k's points: the damped V^-1. False when a damped V is not positive definite.
VARSFM_CPU_CLONES bool SchurSystem::InvertPoints(int k, double mu) {
  for (int p = point_part_begin_[k]; p < point_part_begin_[k + 1]; ++p) {
    // The damped V = [a b c; b d e; c e f] is inverted through its adjugate, its positive
    // definiteness checked by its leading minors (Sylvester's criterion; a NaN fails too)
    // rather than by Eigen's pivoted LDLT, slower at this size (docs/mapper.md, "Speed").
    const Matrix3& u = v_[p];
    const double a = u(0, 0) + mu * ClampDiagonal(u(0, 0)), b = u(0, 1), c = u(0, 2);
    const double d = u(1, 1) + mu * ClampDiagonal(u(1, 1)), e = u(1, 2);
    const double f = u(2, 2) + mu * ClampDiagonal(u(2, 2));
    const double c00 = d * f - e * e, c01 = c * e - b * f, c02 = b * e - c * d;
    const double minor2 = a * d - b * b, det = a * c00 + b * c01 + c * c02;
    if (!(a > 0.0 && minor2 > 0.0 && det > 0.0)) return false;
    const double c12 = b * c - a * e;
    Matrix3& vi = v_inverse_[p];
    vi << c00, c01, c02, c01, a * f - c * c, c12, c02, c12, minor2;
    vi *= 1.0 / det;
  }
  return true;
}

// Rows [row_group_begin_[k], row_group_begin_[k + 1]) of the damped reduced system and its
// right-hand side: the undamped blocks plus mu D, minus T_a W_b^T for every point that couples
// a and b (a <= b), in point order. Each T_a = W_a V^-1 is formed here, where it is used: every
// coupling lies in one part's rows, so it is formed once, and no array of them (as large as W)
// is written and read back.
VARSFM_CPU_CLONES void SchurSystem::EliminatePoints(int k, double mu) {
  std::vector<double> term(3 * static_cast<size_t>(max_block_size_));
  const int row_begin = row_group_begin_[k], row_end = row_group_begin_[k + 1];
  for (int a = row_begin; a < row_end; ++a) {
    const int ta = blocks_[a].tangent;
    const size_t begin = pair_offset_[pair_begin_[a]];
    const size_t end =
        a + 1 < num_column_blocks_ ? pair_offset_[pair_begin_[a + 1]] : s_blocks_.size();
    std::copy(s_blocks_.begin() + begin, s_blocks_.begin() + end, work_.begin() + begin);
    double* d = &work_[begin];  // (a, a) is the first block of its row
    for (int i = 0; i < ta; ++i) d[i * ta + i] += mu * ClampDiagonal(d[i * ta + i]);
    for (int i = 0; i < ta; ++i) rhs_[blocks_[a].column + i] = -g_c_[blocks_[a].column + i];
  }
  for (const int p : group_points_[k]) {
    const int begin = point_couplings_begin_[p], end = point_couplings_begin_[p + 1];
    const Eigen::Vector3d& gp = g_p_[p];
    for (int a = begin; a < end; ++a) {
      const int block_a = couplings_[a].block;
      if (block_a < row_begin) continue;
      if (block_a >= row_end) break;  // couplings are in block order
      const int ta = blocks_[block_a].tangent;
      const int column = blocks_[block_a].column;
      SchurTerm(&w_[couplings_[a].offset], v_inverse_[p], ta, term.data());
      const double* __restrict T = term.data();
      for (int j = 0; j < ta; ++j)
        rhs_[column + j] += T[j] * gp[0] + T[ta + j] * gp[1] + T[2 * ta + j] * gp[2];
      // S_ab -= T_a W_b^T for a <= b. Couplings and each block row are in block order, so one
      // walk along the row finds every b.
      int pair = pair_begin_[block_a];
      for (int b = a; b < end; ++b) {
        const int block_b = couplings_[b].block;
        while (pair_block_[pair] < block_b) ++pair;
        const int tb = blocks_[block_b].tangent;
        const double* __restrict Wb = &w_[couplings_[b].offset];
        double* __restrict out = &work_[pair_offset_[pair]];
        if (ta == 9 && tb == 9) {  // two image blocks: the common case, unrolled
          SubtractSchurTerm9(T, Wb, out);
          continue;
        }
        for (int c = 0; c < tb; ++c) {
          const double w0 = Wb[c], w1 = Wb[tb + c], w2 = Wb[2 * tb + c];
          double* __restrict o = out + c * ta;
          for (int j = 0; j < ta; ++j) o[j] -= T[j] * w0 + T[ta + j] * w1 + T[2 * ta + j] * w2;
        }
      }
    }
  }
}

// Part k's points' steps delta_p = V^-1 (-g_p - W^T delta_c), with their terms of the model
// decrease. False when a step is not finite.
VARSFM_CPU_CLONES bool SchurSystem::BackSubstitute(int k) {
  for (int p = point_part_begin_[k]; p < point_part_begin_[k + 1]; ++p) {
    Eigen::Vector3d b = -g_p_[p];
    for (int a = point_couplings_begin_[p]; a < point_couplings_begin_[p + 1]; ++a) {
      const Block& ba = blocks_[couplings_[a].block];
      const double* W = &w_[couplings_[a].offset];  // column-major tangent x 3
      for (int c = 0; c < 3; ++c)
        for (int j = 0; j < ba.tangent; ++j)
          b[c] -= W[c * ba.tangent + j] * delta_c_[ba.column + j];
    }
    delta_p_[p] = v_inverse_[p] * b;
    if (!delta_p_[p].allFinite()) return false;
    point_g_delta_[p] = g_p_[p].dot(delta_p_[p]);
    double dDd = 0.0;
    for (int i = 0; i < 3; ++i) dDd += ClampDiagonal(v_[p](i, i)) * delta_p_[p][i] * delta_p_[p][i];
    point_dDd_[p] = dDd;
  }
  return true;
}

}  // namespace varsfm
