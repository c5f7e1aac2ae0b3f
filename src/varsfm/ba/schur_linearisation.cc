#include "varsfm/ba/schur_system.h"

#include <algorithm>
#include <cmath>

// The linearisation of the Schur system: residuals, their Jacobians in the blocks' tangent
// coordinates corrected for the loss (Triggs et al., "Bundle adjustment - a modern synthesis",
// 2000, sec. 3.3), and the normal equations' blocks J^T J and J^T r.

namespace varsfm {
namespace {

// Residuals ahead whose cost function EvaluatePart prefetches.
constexpr int kPrefetchDistance = 4;

// out(j, c) += sum_i A(i, j) B(i, c) for row-major A (n x ta) and B (n x tb); out column-major
// with leading dimension ld. Two rows (a reprojection residual) written out: the compiler
// vectorises the contiguous inner loop.
inline void AddTransposeProduct(const double* __restrict A, int ta, const double* __restrict B,
                                int tb, int n, double* __restrict out, int ld) {
  if (n == 2 && ta == 9 && tb == 9 && ld == 9) {  // two image blocks: the common case, unrolled
    for (int c = 0; c < 9; ++c) {
      const double b0 = B[c], b1 = B[9 + c];
      for (int j = 0; j < 9; ++j) out[c * 9 + j] += A[j] * b0 + A[9 + j] * b1;
    }
    return;
  }
  if (n == 2) {
    const double* A1 = A + ta;
    const double* B1 = B + tb;
    for (int c = 0; c < tb; ++c) {
      const double b0 = B[c], b1 = B1[c];
      double* o = out + static_cast<size_t>(c) * ld;
      for (int j = 0; j < ta; ++j) o[j] += A[j] * b0 + A1[j] * b1;
    }
    return;
  }
  for (int c = 0; c < tb; ++c) {
    double* o = out + static_cast<size_t>(c) * ld;
    for (int i = 0; i < n; ++i) {
      const double b = B[i * tb + c];
      for (int j = 0; j < ta; ++j) o[j] += A[i * ta + j] * b;
    }
  }
}

}  // namespace

// Each part evaluates its residuals (whole points: their W, V and g_p are its own); the blocks
// and gradient entries that several parts write are summed afterwards in part order.
bool SchurSystem::Evaluate(bool linearise, double* cost) {
  if (linearise)
    for (Block& b : blocks_)
      if (!UpdatePlusJacobian(&b)) return false;
  runner_.Run([&](int k) { part_ok_[k] = EvaluatePart(k, linearise); });
  if (!AllPartsOk()) return false;
  double total = 0.0, squared_norm = 0.0;
  for (const PartScratch& part : parts_) {
    total += part.cost;
    squared_norm += part.squared_norm;
  }
  *cost = total;
  squared_norm_ = squared_norm;
  if (!linearise) return true;
  g_c_ = parts_[0].g;
  for (int k = 1; k < kParts; ++k) g_c_ += parts_[k].g;
  for (const ResidualPair& pair : residual_pairs_) {
    double* out = &s_blocks_[pair.offset];
    for (size_t j = 0; j < pair.size; ++j) {
      double sum = parts_[0].s[pair.compact + j];
      for (int k = 1; k < kParts; ++k) sum += parts_[k].s[pair.compact + j];
      out[j] = sum;
    }
  }
  return true;
}

// The max-norm of the gradient J^T r (tangent coordinates).
double SchurSystem::GradientMaxNorm() const {
  double m = num_columns_ > 0 ? g_c_.cwiseAbs().maxCoeff() : 0.0;
  for (const Eigen::Vector3d& g : g_p_) m = std::max(m, g.cwiseAbs().maxCoeff());
  return m;
}

// Point p's blocks of the normal equations, V, g_p and its couplings' W, to zero.
void SchurSystem::ZeroPoint(int p) {
  v_[p].setZero();
  g_p_[p].setZero();
  const int c_begin = point_couplings_begin_[p], c_end = point_couplings_begin_[p + 1];
  if (c_end > c_begin)
    std::fill(w_.begin() + couplings_[c_begin].offset,
              w_.begin() + couplings_[c_end - 1].offset +
                  3 * blocks_[couplings_[c_end - 1].block].tangent,
              0.0);
}

// One part's residuals into its buffers (see Evaluate); the W, V and g_p of its points are
// zeroed and summed here, as no other part writes them. False when a cost function fails.
// The products are plain loops: the blocks are a few parameters wide, where Eigen's
// dynamic-size expressions cost more than the arithmetic (docs/mapper.md, "Speed").
VARSFM_CPU_CLONES bool SchurSystem::EvaluatePart(int k, bool linearise) {
  PartScratch& part = parts_[k];
  part.cost = 0.0;
  part.squared_norm = 0.0;
  if (linearise) {
    std::fill(part.s.begin(), part.s.end(), 0.0);
    part.g.setZero(num_columns_);
  }
  double* r = part.r.data();
  double total = 0.0;
  int current_point = -1;
  const int end = residual_part_begin_[k + 1];
  for (int i = residual_part_begin_[k]; i < end; ++i) {
    const Residual& res = residuals_[i];
    // A part's residuals come point by point: a point's V, g_p and W are zeroed at its first
    // residual, while they are in cache (zeroing every W up front, tens of MB on a long
    // sequence, left each accumulation a cache miss).
    if (linearise && res.point >= 0 && res.point != current_point) {
      current_point = res.point;
      ZeroPoint(current_point);
    }
    // The cost functions may be scattered over the heap (a ceres::Problem's: one allocation
    // each, in the order the allocator had free chunks): reading the next ones early hides
    // the cache misses.
    if (i + kPrefetchDistance < end) {
      const char* next = reinterpret_cast<const char*>(residuals_[i + kPrefetchDistance].cost);
      __builtin_prefetch(next);
      __builtin_prefetch(next + 64);
    }
    const int n = res.cost->num_residuals();
    const int num_params = res.count;
    const int* block_of = &block_of_[res.begin];
    for (int j = 0; j < num_params; ++j)
      part.jacobians[j] = linearise && block_of[j] >= 0 ? part.raw[j].data() : nullptr;
    if (!res.cost->Evaluate(&values_[res.begin], r, linearise ? part.jacobians.data() : nullptr))
      return false;
    double squared = 0.0;
    for (int j = 0; j < n; ++j) squared += r[j] * r[j];
    double rho[3] = {squared, 1.0, 0.0};
    if (res.loss) res.loss->Evaluate(squared, rho);
    total += 0.5 * rho[0];
    part.squared_norm += squared;
    if (!linearise) continue;

    // The Jacobians in tangent coordinates (row-major n x tangent): J P, P sparse.
    for (int j = 0; j < num_params; ++j) {
      if (block_of[j] < 0) continue;
      const Block& b = blocks_[block_of[j]];
      const double* J = part.raw[j].data();
      double* Jt = part.tangent[j].data();
      if (!b.manifold) {
        std::copy_n(J, n * b.size, Jt);
        continue;
      }
      if (n == 2) {  // a reprojection: each tangent column summed in registers
        const double* J1 = J + b.size;
        const PlusEntry* e = b.plus_entries.data();
        const PlusEntry* e_end = e + b.plus_entries.size();
        for (int c = 0; c < b.tangent; ++c) {
          double sum0 = 0.0, sum1 = 0.0;
          for (; e != e_end && e->col == c; ++e) {
            sum0 += J[e->row] * e->value;
            sum1 += J1[e->row] * e->value;
          }
          Jt[c] = sum0;
          Jt[b.tangent + c] = sum1;
        }
        continue;
      }
      std::fill_n(Jt, n * b.tangent, 0.0);
      for (const PlusEntry& e : b.plus_entries)
        for (int row = 0; row < n; ++row)
          Jt[row * b.tangent + e.col] += J[row * b.size + e.row] * e.value;
    }
    // Triggs' correction (Ceres' Corrector): sqrt(rho') scales the residual and Jacobian,
    // with a rank-one term when the loss is locally convex (rho'' > 0).
    if (res.loss) {
      const double sqrt_rho1 = std::sqrt(rho[1]);
      double alpha = 0.0, residual_scaling = sqrt_rho1;
      if (squared > 0.0 && rho[2] > 0.0) {
        alpha = 1.0 - std::sqrt(1.0 + 2.0 * squared * rho[2] / rho[1]);
        residual_scaling = sqrt_rho1 / (1.0 - alpha);
      }
      for (int j = 0; j < num_params; ++j) {
        if (block_of[j] < 0) continue;
        const int t = blocks_[block_of[j]].tangent;
        double* Jt = part.tangent[j].data();
        if (alpha != 0.0) {
          for (int c = 0; c < t; ++c) {
            double rJ = 0.0;
            for (int row = 0; row < n; ++row) rJ += r[row] * Jt[row * t + c];
            for (int row = 0; row < n; ++row) Jt[row * t + c] -= (alpha / squared) * r[row] * rJ;
          }
        }
        for (int c = 0; c < n * t; ++c) Jt[c] *= sqrt_rho1;
      }
      for (int j = 0; j < n; ++j) r[j] *= residual_scaling;
    }
    // Accumulate J^T J and J^T r: block pairs into S (upper triangle), the point's V and
    // g_p, the couplings W.
    const int pk = res.point_parameter;
    const double* Jp = pk >= 0 ? part.tangent[pk].data() : nullptr;
    for (int a = 0; a < num_params; ++a) {
      if (block_of[a] < 0) continue;
      const Block& ba = blocks_[block_of[a]];
      const int ta = ba.tangent;
      const double* Ja = part.tangent[a].data();
      double* g = a == pk ? g_p_[ba.point].data() : part.g.data() + ba.column;
      AddTransposeProduct(Ja, ta, r, 1, n, g, 1);
      if (a == pk) {
        AddTransposeProduct(Ja, 3, Ja, 3, n, v_[ba.point].data(), 3);  // column-major 3 x 3
        continue;
      }
      for (int b = 0; b < num_params; ++b) {
        if (b == pk || block_of[b] < 0) continue;
        const Block& bb = blocks_[block_of[b]];
        if (bb.column < ba.column) continue;
        AddTransposeProduct(Ja, ta, part.tangent[b].data(), bb.tangent, n,
                            &part.s[compact_of_pair_[PairIndex(block_of[a], block_of[b])]], ta);
      }
      if (Jp)  // W: column-major ta x 3
        AddTransposeProduct(Ja, ta, Jp, 3, n, &w_[couplings_[coupling_of_[res.begin + a]].offset],
                            ta);
    }
  }
  part.cost = total;
  return true;
}

// The plus-Jacobian of a manifold block at its current value, and its non-zeros.
bool SchurSystem::UpdatePlusJacobian(Block* b) {
  if (!b->manifold) return true;
  b->plus_jacobian.resize(b->size, b->tangent);
  if (!b->manifold->PlusJacobian(b->x, b->plus_jacobian.data())) return false;
  b->plus_entries.clear();
  for (int col = 0; col < b->tangent; ++col)
    for (int row = 0; row < b->size; ++row)
      if (const double v = b->plus_jacobian(row, col); v != 0.0)
        b->plus_entries.push_back({row, col, v});
  return true;
}

}  // namespace varsfm
