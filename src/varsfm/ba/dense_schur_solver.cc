#include "varsfm/ba/dense_schur_solver.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/manifold.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "varsfm/ba/cholesky.h"
#include "varsfm/util/timer.h"

namespace varsfm {
namespace {

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using Matrix3 = Eigen::Matrix3d;

// Ceres' defaults (solver.h): LM diagonal bounds, trust-region bounds, step acceptance.
constexpr double kMinDiagonal = 1e-6;
constexpr double kMaxDiagonal = 1e32;
constexpr double kMaxRadius = 1e16;
constexpr double kMinRadius = 1e-32;
constexpr double kMinRelativeDecrease = 1e-3;

double ClampDiagonal(double d) { return std::clamp(d, kMinDiagonal, kMaxDiagonal); }

// The solver's loops over residuals and points are compiled twice, for x86-64-v3 (AVX2, FMA)
// and for the baseline, and the loader picks the one the CPU runs (GCC's function
// multi-versioning): Debian's packages target the baseline, and the 9 x 9 block products run
// ~1.5x faster four doubles wide. FMA rounds differently: a result is the same bit for bit on
// one machine, not between CPUs with and without AVX2.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define VARSFM_CPU_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define VARSFM_CPU_CLONES
#endif

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

// A non-zero of a manifold's plus-Jacobian: a product of subsets and rotations is mostly zeros
// (the 14 x 9 Jacobian of an image block has 18 non-zeros). A block keeps them column by
// column, each column's by row.
struct PlusEntry {
  int row = 0;
  int col = 0;
  double value = 0.0;
};

// A variable parameter block: either a column range of the reduced system or an eliminated
// point.
struct Block {
  double* x = nullptr;
  int size = 0;
  int tangent = 0;
  const ceres::Manifold* manifold = nullptr;  // null: Euclidean
  int column = -1;                            // first column in the reduced system
  int point = -1;                             // index of the eliminated point
  RowMatrix plus_jacobian;                    // size x tangent at x (manifold blocks only)
  std::vector<PlusEntry> plus_entries;        // its non-zeros
};

// One (non-eliminated block, point) pair of the Schur complement: W = sum J_b^T J_p over the
// residuals of the point that involve the block, stored column-major tangent_b x 3 at `offset`.
struct Coupling {
  int block = 0;
  size_t offset = 0;
};

// A residual block; its parameter blocks are entries [begin, begin + count) of the flat arrays
// (one allocation for all residuals: the per-residual walk is memory-bound).
struct Residual {
  const ceres::CostFunction* cost = nullptr;
  const ceres::LossFunction* loss = nullptr;
  int begin = 0;
  int count = 0;
  int point_parameter = -1;  // which parameter block is the eliminated point, if any
  int point = -1;            // that point's index
};

// A block (a, b) of the reduced system that residuals write directly (two non-eliminated blocks
// of one residual: an image's diagonal block, an image with a shared camera block): at `offset`
// in the blocks, at `compact` in each part's buffer.
struct ResidualPair {
  size_t offset = 0;
  size_t compact = 0;
  size_t size = 0;
};

// The work is cut into a fixed number of parts, whatever the number of threads, and every sum
// over parts is taken in part order: the result is then the same bit for bit with any number of
// threads (Ceres' multi-threaded sums depend on the scheduling).
constexpr int kParts = 8;

// Residuals ahead whose cost function EvaluatePart prefetches.
constexpr int kPrefetchDistance = 4;

// Runs fn(0) ... fn(kParts - 1), on the calling thread alone or on up to `num_threads` threads.
class PartRunner {
 public:
  explicit PartRunner(int num_threads) {
    if (num_threads > 1) arena_.emplace(std::min(num_threads, kParts));
  }
  template <typename Fn>
  void Run(const Fn& fn) {
    if (!arena_) {
      for (int k = 0; k < kParts; ++k) fn(k);
      return;
    }
    arena_->execute([&] { tbb::parallel_for(0, kParts, [&](int k) { fn(k); }); });
  }

 private:
  std::optional<tbb::task_arena> arena_;
};

// One part's buffers for Evaluate: its residuals' scratch and its share of the sums that several
// parts write (the reduced system's columns' gradient, the blocks that residuals couple directly,
// the cost).
struct PartScratch {
  std::vector<double> r;
  std::vector<std::vector<double>> raw, tangent;
  std::vector<double*> jacobians;
  std::vector<double> s;  // residual-coupled blocks, at their compact offsets
  Eigen::VectorXd g;
  double cost = 0.0;
  double squared_norm = 0.0;  // sum |r|^2, without the loss
};

class DenseSchurProblem {
 public:
  // Fails (ok() false) when a residual uses a block that was not added to the problem.
  DenseSchurProblem(const std::vector<double*>& eliminate,
                    DenseSchurOptions::Factorization factorization, int num_threads,
                    const SchurProblem& problem)
      : values_(problem.parameters()), factorization_(factorization), runner_(num_threads) {
    residuals_.resize(problem.residual_blocks().size());
    for (size_t i = 0; i < residuals_.size(); ++i) {
      const SchurProblem::ResidualBlock& block = problem.residual_blocks()[i];
      Residual& r = residuals_[i];
      r.cost = block.cost;
      r.loss = block.loss;
      r.begin = block.begin;
      r.count = block.count;
      max_residuals_ = std::max(max_residuals_, r.cost->num_residuals());
      max_parameters_ = std::max(max_parameters_, r.count);
    }
    // The distinct parameter blocks the residuals use, in address order; the variable ones
    // become blocks: columns first, then points.
    std::vector<SchurProblem::ParameterBlock> declared(problem.parameter_blocks());
    const auto by_address = [](const SchurProblem::ParameterBlock& a,
                               const SchurProblem::ParameterBlock& b) { return a.x < b.x; };
    std::sort(declared.begin(), declared.end(), by_address);
    std::vector<double*> sorted_eliminate(eliminate);
    std::sort(sorted_eliminate.begin(), sorted_eliminate.end());
    std::vector<double*> distinct(values_);
    std::sort(distinct.begin(), distinct.end());
    distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
    std::vector<const SchurProblem::ParameterBlock*> info(distinct.size());
    for (size_t i = 0; i < distinct.size(); ++i) {
      const auto it = std::lower_bound(declared.begin(), declared.end(),
                                       SchurProblem::ParameterBlock{distinct[i]}, by_address);
      if (it == declared.end() || it->x != distinct[i]) return;
      info[i] = &*it;
    }
    std::vector<int> block_of_distinct(distinct.size(), -1);
    for (const bool points : {false, true}) {
      for (size_t i = 0; i < distinct.size(); ++i) {
        double* x = distinct[i];
        const SchurProblem::ParameterBlock& declared_block = *info[i];
        const int tangent =
            declared_block.manifold ? declared_block.manifold->TangentSize() : declared_block.size;
        max_block_size_ = std::max(max_block_size_, declared_block.size);
        if (std::binary_search(sorted_eliminate.begin(), sorted_eliminate.end(), x) != points ||
            declared_block.constant || tangent == 0)
          continue;
        Block b;
        b.x = x;
        b.size = declared_block.size;
        b.tangent = tangent;
        b.manifold = declared_block.manifold;
        if (points) {
          b.point = num_points_++;
        } else {
          b.column = num_columns_;
          num_columns_ += b.tangent;
        }
        block_of_distinct[i] = static_cast<int>(blocks_.size());
        blocks_.push_back(std::move(b));
      }
    }
    block_of_.resize(values_.size());
    for (size_t k = 0; k < values_.size(); ++k)
      block_of_[k] =
          block_of_distinct[std::lower_bound(distinct.begin(), distinct.end(), values_[k]) -
                            distinct.begin()];
    // The couplings (point, block), grouped by point and in column order within a point.
    std::vector<std::pair<int, int>> pairs;
    for (Residual& r : residuals_) {
      for (int k = 0; k < r.count; ++k)
        if (block_of_[r.begin + k] >= 0 && blocks_[block_of_[r.begin + k]].point >= 0)
          r.point_parameter = k;
      if (r.point_parameter < 0) continue;
      const int point = blocks_[block_of_[r.begin + r.point_parameter]].point;
      for (int k = 0; k < r.count; ++k)
        if (k != r.point_parameter && block_of_[r.begin + k] >= 0)
          pairs.emplace_back(point, block_of_[r.begin + k]);
    }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    point_couplings_begin_.assign(num_points_ + 1, static_cast<int>(pairs.size()));
    size_t offset = 0;
    for (size_t i = 0; i < pairs.size(); ++i) {
      if (i == 0 || pairs[i].first != pairs[i - 1].first)
        point_couplings_begin_[pairs[i].first] = static_cast<int>(i);
      couplings_.push_back({pairs[i].second, offset});
      offset += 3 * blocks_[pairs[i].second].tangent;
    }
    for (int p = num_points_ - 1; p >= 0; --p)  // points without couplings: empty ranges
      point_couplings_begin_[p] =
          std::min(point_couplings_begin_[p], point_couplings_begin_[p + 1]);
    coupling_of_.assign(values_.size(), -1);
    for (const Residual& r : residuals_) {
      if (r.point_parameter < 0) continue;
      const int point = blocks_[block_of_[r.begin + r.point_parameter]].point;
      const auto first = pairs.begin() + point_couplings_begin_[point];
      const auto last = pairs.begin() + point_couplings_begin_[point + 1];
      for (int k = 0; k < r.count; ++k)
        if (k != r.point_parameter && block_of_[r.begin + k] >= 0)
          coupling_of_[r.begin + k] = static_cast<int>(
              std::lower_bound(first, last, std::pair{point, block_of_[r.begin + k]}) -
              pairs.begin());
    }
    w_.resize(offset);
    t_.resize(offset);
    BuildReducedStructure();
    PartitionResiduals();
    BuildResidualPairs();
    BuildRowGroups();
    v_.resize(num_points_);
    v_inverse_.resize(num_points_);
    g_p_.resize(num_points_);
    delta_p_.resize(num_points_);
    point_g_delta_.resize(num_points_);
    point_dDd_.resize(num_points_);
    for (const Block& b : blocks_) num_parameters_ += b.size;
    ok_ = true;
  }

  bool ok() const { return ok_; }

  int num_columns() const { return num_columns_; }
  double seconds_factorise() const { return seconds_factorise_; }
  // sum |r|^2 (no loss) at the parameters of the last Evaluate.
  double squared_norm() const { return squared_norm_; }
  bool sparse() const { return sparse_; }
  double fill() const { return fill_; }

  // The cost 1/2 sum rho(|r|^2) at the current parameters, and with `linearise` the normal
  // equations' blocks (S, W, V, g) of the loss-corrected Jacobian. False when a cost function
  // fails. Each part evaluates its residuals (whole points: their W, V and g_p are its own); the
  // blocks and gradient entries that several parts write are summed afterwards in part order.
  bool Evaluate(bool linearise, double* cost) {
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
  double GradientMaxNorm() const {
    double m = num_columns_ > 0 ? g_c_.cwiseAbs().maxCoeff() : 0.0;
    for (const Eigen::Vector3d& g : g_p_) m = std::max(m, g.cwiseAbs().maxCoeff());
    return m;
  }

  // Solves (J^T J + mu D) delta = -J^T r through the Schur complement of the points. Returns
  // false when the reduced system is not positive definite. `model_decrease` is the decrease of
  // the linearised cost, -1/2 g^T delta + 1/2 mu delta^T D delta (from the damped equations).
  bool SolveStep(double mu, double* model_decrease, double* step_norm) {
    // V^-1 and T = W V^-1 of every point, then each part's rows of the reduced system and its
    // right-hand side: S + mu D - sum_p T_p W_p^T and -g_c + sum_p T_p g_p.
    runner_.Run([&](int k) { part_ok_[k] = InvertPoints(k, mu); });
    if (!AllPartsOk()) return false;
    work_.resize(s_blocks_.size());
    rhs_.resize(num_columns_);
    runner_.Run([&](int k) { EliminatePoints(k, mu); });
    // Jacobi scaling of the reduced system, then Cholesky of its upper triangle (dense, or
    // sparse for a sequence's banded camera graph).
    Eigen::VectorXd scale(num_columns_);
    for (int a = 0; a < num_column_blocks_; ++a) {
      const int ta = blocks_[a].tangent;
      const double* d = &work_[pair_offset_[pair_begin_[a]]];
      for (int i = 0; i < ta; ++i)
        scale[blocks_[a].column + i] = 1.0 / std::sqrt(std::max(d[i * ta + i], 1e-300));
    }
    delta_c_.resize(num_columns_);
    double dDd = 0.0;
    if (num_columns_ > 0) {
      const Timer factorise;
      const Eigen::VectorXd scaled_rhs = scale.asDiagonal() * rhs_;
      Eigen::VectorXd y;
      if (sparse_) {
        FillSparse(scale);
        if (!sparse_llt_.Factorize(sparse_s_)) return false;
        y = sparse_llt_.Solve(scaled_rhs);
      } else {
        Eigen::MatrixXd s = Eigen::MatrixXd::Zero(num_columns_, num_columns_);
        FillDense(scale, &s);
        if (!SolveDenseCholesky(&s, scaled_rhs, &y)) return false;
      }
      seconds_factorise_ += factorise.Seconds();
      delta_c_ = scale.asDiagonal() * y;
      if (!delta_c_.allFinite()) return false;
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
    *step_norm = std::sqrt(norm2);
    step_g_delta_ = g_delta;
    step_dDd_ = dDd;
    return true;
  }

  // Powell's dogleg (Nocedal & Wright, "Numerical Optimization", 2nd ed., sec. 4.1; Ceres'
  // DoglegStrategy) combines the Gauss-Newton step p (the last SolveStep, with its small mu)
  // and the Cauchy point along u = D^-1 g, the gradient in the Jacobi-scaled coordinates. The
  // model of every step a p + b u follows from five scalars: with (H + mu D) p = -g,
  // p^T H p = -g.p - mu p^T D p and u^T H p = -g.u - mu g.p; only u^T H u needs the blocks.
  struct DoglegTerms {
    double mu = 0.0;
    double g_p = 0.0;    // g . p
    double p_D_p = 0.0;  // p^T D p
    double g_u = 0.0;    // g . u = |u|_D^2
    double u_H_u = 0.0;
  };

  // Keeps the last step as the Gauss-Newton step p (solved with damping mu) and computes u.
  DoglegTerms KeepGaussNewtonStep(double mu) {
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

  // The step a p + b u into delta (for Step()); returns its Euclidean norm.
  double SetDoglegStep(double a, double b) {
    delta_c_ = a * gn_c_ + b * u_c_;
    double norm2 = delta_c_.squaredNorm();
    for (int p = 0; p < num_points_; ++p) {
      delta_p_[p] = a * gn_p_[p] + b * u_p_[p];
      norm2 += delta_p_[p].squaredNorm();
    }
    return std::sqrt(norm2);
  }

  // x <- x [+] delta, keeping the previous values for Restore(). False when a manifold fails.
  bool Step() {
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

  void Restore() {
    const double* saved = backup_.data();
    for (const Block& b : blocks_) {
      std::copy_n(saved, b.size, b.x);
      saved += b.size;
    }
  }

  double ParameterNorm() const {
    double sum = 0.0;
    for (const Block& b : blocks_)
      for (int i = 0; i < b.size; ++i) sum += b.x[i] * b.x[i];
    return std::sqrt(sum);
  }

 private:
  bool AllPartsOk() const {
    return std::find(part_ok_.begin(), part_ok_.end(), false) == part_ok_.end();
  }

  // One part's residuals into its buffers (see Evaluate); the W, V and g_p of its points are
  // zeroed and summed here, as no other part writes them. False when a cost function fails.
  // The products are plain loops: the blocks are a few parameters wide, where Eigen's
  // dynamic-size expressions cost more than the arithmetic (they took 40 % of the solver's time).
  VARSFM_CPU_CLONES bool EvaluatePart(int k, bool linearise) {
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

  // Point p's blocks of the normal equations, V, g_p and its couplings' W, to zero.
  void ZeroPoint(int p) {
    v_[p].setZero();
    g_p_[p].setZero();
    const int c_begin = point_couplings_begin_[p], c_end = point_couplings_begin_[p + 1];
    if (c_end > c_begin)
      std::fill(w_.begin() + couplings_[c_begin].offset,
                w_.begin() + couplings_[c_end - 1].offset +
                    3 * blocks_[couplings_[c_end - 1].block].tangent,
                0.0);
  }

  // Part k's points: the damped V^-1, and T = W V^-1 for each coupling (column-major
  // tangent x 3, at W's offset in t_). False when a damped V is not positive definite.
  VARSFM_CPU_CLONES bool InvertPoints(int k, double mu) {
    for (int p = point_part_begin_[k]; p < point_part_begin_[k + 1]; ++p) {
      // The damped V = [a b c; b d e; c e f] is inverted through its adjugate, its positive
      // definiteness checked by its leading minors (Sylvester's criterion; a NaN fails too)
      // rather than by Eigen's pivoted LDLT: bundler/ET's solves 0.047 -> 0.035 s (median of 8).
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
      for (int a = point_couplings_begin_[p]; a < point_couplings_begin_[p + 1]; ++a) {
        const int ta = blocks_[couplings_[a].block].tangent;
        const double* __restrict W = &w_[couplings_[a].offset];
        double* __restrict T = &t_[couplings_[a].offset];
        for (int c = 0; c < 3; ++c)
          for (int j = 0; j < ta; ++j)
            T[c * ta + j] = W[j] * vi(0, c) + W[ta + j] * vi(1, c) + W[2 * ta + j] * vi(2, c);
      }
    }
    return true;
  }

  // Rows [row_group_begin_[k], row_group_begin_[k + 1]) of the damped reduced system and its
  // right-hand side: the undamped blocks plus mu D, minus T_a W_b^T for every point that couples
  // a and b (a <= b), in point order.
  VARSFM_CPU_CLONES void EliminatePoints(int k, double mu) {
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
        const double* __restrict T = &t_[couplings_[a].offset];
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
  VARSFM_CPU_CLONES bool BackSubstitute(int k) {
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
      for (int i = 0; i < 3; ++i)
        dDd += ClampDiagonal(v_[p](i, i)) * delta_p_[p][i] * delta_p_[p][i];
      point_dDd_[p] = dDd;
    }
    return true;
  }

  // Cuts the residuals into kParts runs of whole points (each point's residuals in one part,
  // about as many residuals in each part), residuals without a point spread by their index.
  // Within a part the residuals come point by point (those without a point first), each point's
  // in their order in the problem.
  void PartitionResiduals() {
    const int n = static_cast<int>(residuals_.size());
    std::vector<int> per_point(num_points_ + 1, 0);
    for (Residual& r : residuals_) {
      if (r.point_parameter < 0) continue;
      r.point = blocks_[block_of_[r.begin + r.point_parameter]].point;
      ++per_point[r.point + 1];
    }
    for (int p = 0; p < num_points_; ++p) per_point[p + 1] += per_point[p];  // residuals before
    const int with_points = per_point[num_points_];
    const auto part_of_point = [&](int p) {
      return with_points > 0
                 ? std::min(kParts - 1, static_cast<int>(static_cast<int64_t>(per_point[p]) *
                                                         kParts / with_points))
                 : 0;
    };
    point_part_begin_.assign(kParts + 1, num_points_);
    for (int p = num_points_ - 1; p >= 0; --p)
      for (int k = 0; k <= part_of_point(p); ++k) point_part_begin_[k] = p;
    std::vector<int> part(n);
    for (int i = 0; i < n; ++i)
      part[i] = residuals_[i].point >= 0 ? part_of_point(residuals_[i].point)
                                         : static_cast<int>(static_cast<int64_t>(i) * kParts / n);
    std::vector<int> order(n);
    for (int i = 0; i < n; ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
      return part[a] != part[b] ? part[a] < part[b] : residuals_[a].point < residuals_[b].point;
    });
    std::vector<Residual> sorted(n);
    residual_part_begin_.assign(kParts + 1, n);
    for (int i = n - 1; i >= 0; --i) {
      sorted[i] = residuals_[order[i]];
      residual_part_begin_[part[order[i]]] = i;
    }
    for (int k = kParts - 1; k >= 0; --k)  // parts without residuals: empty ranges
      residual_part_begin_[k] = std::min(residual_part_begin_[k], residual_part_begin_[k + 1]);
    residuals_ = std::move(sorted);
  }

  // The blocks residuals write directly, with their offsets in the parts' compact buffers; the
  // parts' buffers.
  void BuildResidualPairs() {
    compact_of_pair_.assign(pair_offset_.size(), 0);
    std::vector<bool> used(pair_offset_.size(), false);
    for (const Residual& r : residuals_)
      for (int i = 0; i < r.count; ++i)
        for (int j = 0; j < r.count; ++j) {
          const int a = block_of_[r.begin + i], b = block_of_[r.begin + j];
          if (i == r.point_parameter || j == r.point_parameter || a < 0 || b < 0 ||
              blocks_[b].column < blocks_[a].column)
            continue;
          used[PairIndex(a, b)] = true;
        }
    size_t compact = 0;
    for (int a = 0; a < num_column_blocks_; ++a)
      for (int k = pair_begin_[a]; k < pair_begin_[a + 1]; ++k) {
        if (!used[k]) continue;
        const size_t size =
            static_cast<size_t>(blocks_[a].tangent) * blocks_[pair_block_[k]].tangent;
        residual_pairs_.push_back({pair_offset_[k], compact, size});
        compact_of_pair_[k] = compact;
        compact += size;
      }
    for (PartScratch& part : parts_) {  // and the parts' per-residual scratch
      part.s.assign(compact, 0.0);
      part.r.resize(max_residuals_);
      part.jacobians.assign(max_parameters_, nullptr);
      part.raw.assign(max_parameters_, std::vector<double>(max_residuals_ * max_block_size_));
      part.tangent.assign(max_parameters_, std::vector<double>(max_residuals_ * max_block_size_));
    }
  }

  // Cuts the reduced system's block rows into kParts runs of about equal elimination work (the
  // point pairs that update each row); SolveStep gives each run to one part, which applies every
  // point's terms to its rows in point order, as one thread would.
  void BuildRowGroups() {
    std::vector<double> work(num_column_blocks_ + 1, 0.0);
    for (int a = 0; a < num_column_blocks_; ++a) work[a] = pair_begin_[a + 1] - pair_begin_[a];
    for (int p = 0; p < num_points_; ++p)
      for (int i = point_couplings_begin_[p]; i < point_couplings_begin_[p + 1]; ++i)
        work[couplings_[i].block] += point_couplings_begin_[p + 1] - i;
    double total = 0.0;
    for (int a = 0; a < num_column_blocks_; ++a) total += work[a];
    row_group_begin_.assign(kParts + 1, num_column_blocks_);
    row_group_begin_[0] = 0;
    double done = 0.0;
    int group = 1;
    for (int a = 0; a < num_column_blocks_ && group < kParts; ++a) {
      done += work[a];
      while (group < kParts && done >= total * group / kParts) row_group_begin_[group++] = a + 1;
    }
    std::vector<int> group_of(num_column_blocks_);
    for (int g = 0; g < kParts; ++g)
      for (int a = row_group_begin_[g]; a < row_group_begin_[g + 1]; ++a) group_of[a] = g;
    group_points_.assign(kParts, {});
    for (int p = 0; p < num_points_; ++p) {
      int last = -1;  // couplings are in block order: a point's groups come in order
      for (int i = point_couplings_begin_[p]; i < point_couplings_begin_[p + 1]; ++i) {
        const int g = group_of[couplings_[i].block];
        if (g != last) group_points_[g].push_back(p);
        last = g;
      }
    }
  }

  // The reduced system's block structure: block (a, b), a <= b, exists when a residual or a
  // point involves both; each block row is sorted, its diagonal block first. The system is
  // factorised sparse when it has many columns and few blocks (a sequence: each image shares
  // points with its neighbours only), dense otherwise.
  void BuildReducedStructure() {
    num_column_blocks_ = 0;
    while (num_column_blocks_ < static_cast<int>(blocks_.size()) &&
           blocks_[num_column_blocks_].column >= 0)
      ++num_column_blocks_;
    std::vector<std::vector<int>> rows(num_column_blocks_);
    for (int a = 0; a < num_column_blocks_; ++a) rows[a].push_back(a);
    for (const Residual& r : residuals_)
      for (int i = 0; i < r.count; ++i)
        for (int j = 0; j < r.count; ++j) {
          const int a = block_of_[r.begin + i], b = block_of_[r.begin + j];
          if (a >= 0 && b > a && blocks_[a].column >= 0 && blocks_[b].column >= 0)
            rows[a].push_back(b);
        }
    for (int p = 0; p < num_points_; ++p)
      for (int i = point_couplings_begin_[p]; i < point_couplings_begin_[p + 1]; ++i)
        for (int j = i + 1; j < point_couplings_begin_[p + 1]; ++j)
          rows[couplings_[i].block].push_back(couplings_[j].block);
    pair_begin_.assign(num_column_blocks_ + 1, 0);
    pair_block_.clear();
    pair_offset_.clear();
    size_t offset = 0;
    for (int a = 0; a < num_column_blocks_; ++a) {
      std::sort(rows[a].begin(), rows[a].end());
      rows[a].erase(std::unique(rows[a].begin(), rows[a].end()), rows[a].end());
      pair_begin_[a] = static_cast<int>(pair_block_.size());
      for (const int b : rows[a]) {
        pair_block_.push_back(b);
        pair_offset_.push_back(offset);
        offset += static_cast<size_t>(blocks_[a].tangent) * blocks_[b].tangent;
      }
      std::vector<int>().swap(rows[a]);
    }
    pair_begin_[num_column_blocks_] = static_cast<int>(pair_block_.size());
    pair_block_.push_back(std::numeric_limits<int>::max());  // sentinel for the row walks
    s_blocks_.assign(offset, 0.0);
    g_c_.resize(num_columns_);
    // Sparse for a large system (beyond 1500 columns, ~170 images, where a dense factorisation
    // costs over a GFLOP an iteration) or a mid-sized one whose blocks fill less than a quarter
    // of it. Measured on bench/scale's street sequence (2026-12-01): the final global BA of 200
    // images (1,800 columns, 8 iterations) spent 3.1-4.5 s in the dense solves and 3.1 s in the
    // sparse ones (the points' Schur terms dominate both); one of 370 images (3,330 columns)
    // spent 1.0 s per dense solve. At 100 images the blocks fill 59 % of the system.
    const double upper = 0.5 * static_cast<double>(num_columns_) * (num_columns_ + 1);
    fill_ = upper > 0.0 ? static_cast<double>(offset) / upper : 0.0;
    sparse_ = factorization_ == DenseSchurOptions::Factorization::kSparse ||
              (factorization_ == DenseSchurOptions::Factorization::kAuto &&
               (num_columns_ > 1500 ||
                (num_columns_ > 300 && static_cast<double>(offset) < 0.25 * upper)));
    if (!sparse_) return;
    // The pattern once (upper triangle, column-major); each block column is a contiguous run of
    // its column's non-zeros, recorded in value_starts_ for FillSparse.
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(offset);
    for (int a = 0; a < num_column_blocks_; ++a)
      for (int k = pair_begin_[a]; k < pair_begin_[a + 1]; ++k) {
        const Block& ba = blocks_[a];
        const Block& bb = blocks_[pair_block_[k]];
        for (int c = 0; c < bb.tangent; ++c)
          for (int j = 0; j < ba.tangent && (pair_block_[k] != a || j <= c); ++j)
            triplets.emplace_back(ba.column + j, bb.column + c, 1.0);
      }
    sparse_s_.resize(num_columns_, num_columns_);
    sparse_s_.setFromTriplets(triplets.begin(), triplets.end());
    sparse_s_.makeCompressed();
    pair_value_begin_.resize(pair_block_.size() - 1);
    std::vector<int> starts;
    for (int a = 0; a < num_column_blocks_; ++a)
      for (int k = pair_begin_[a]; k < pair_begin_[a + 1]; ++k) {
        const Block& bb = blocks_[pair_block_[k]];
        pair_value_begin_[k] = static_cast<int>(starts.size());
        for (int c = 0; c < bb.tangent; ++c) {
          const int col = bb.column + c;
          const int* rows_begin = sparse_s_.innerIndexPtr() + sparse_s_.outerIndexPtr()[col];
          const int* rows_end = sparse_s_.innerIndexPtr() + sparse_s_.outerIndexPtr()[col + 1];
          starts.push_back(
              static_cast<int>(std::lower_bound(rows_begin, rows_end, blocks_[a].column) -
                               sparse_s_.innerIndexPtr()));
        }
      }
    value_starts_ = std::move(starts);
    sparse_llt_.AnalyzePattern(sparse_s_);
  }

  // The index of block (a, b), a <= b, in pair_block_ / pair_offset_.
  int PairIndex(int a, int b) const {
    const auto first = pair_block_.begin() + pair_begin_[a];
    const auto last = pair_block_.begin() + pair_begin_[a + 1];
    return static_cast<int>(std::lower_bound(first, last, b) - pair_block_.begin());
  }

  // The scaled reduced system (work_) into the sparse matrix's values / a dense upper triangle.
  void FillSparse(const Eigen::VectorXd& scale) {
    double* values = sparse_s_.valuePtr();
    for (int a = 0; a < num_column_blocks_; ++a) {
      const Block& ba = blocks_[a];
      for (int k = pair_begin_[a]; k < pair_begin_[a + 1]; ++k) {
        const Block& bb = blocks_[pair_block_[k]];
        const double* block = &work_[pair_offset_[k]];
        for (int c = 0; c < bb.tangent; ++c) {
          const int rows = pair_block_[k] == a ? c + 1 : ba.tangent;
          double* out = values + value_starts_[pair_value_begin_[k] + c];
          const double sc = scale[bb.column + c];
          for (int j = 0; j < rows; ++j)
            out[j] = block[c * ba.tangent + j] * scale[ba.column + j] * sc;
        }
      }
    }
  }

  void FillDense(const Eigen::VectorXd& scale, Eigen::MatrixXd* s) const {
    for (int a = 0; a < num_column_blocks_; ++a) {
      const Block& ba = blocks_[a];
      for (int k = pair_begin_[a]; k < pair_begin_[a + 1]; ++k) {
        const Block& bb = blocks_[pair_block_[k]];
        const double* block = &work_[pair_offset_[k]];
        for (int c = 0; c < bb.tangent; ++c)
          for (int j = 0; j < ba.tangent; ++j)
            (*s)(ba.column + j, bb.column + c) =
                block[c * ba.tangent + j] * scale[ba.column + j] * scale[bb.column + c];
      }
    }
  }

  static bool UpdatePlusJacobian(Block* b) {
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

  std::vector<Block> blocks_;
  std::vector<Residual> residuals_;
  std::vector<double*> values_;   // per residual parameter: the cost function's block
  std::vector<int> block_of_;     // its index in blocks_, -1 when constant
  std::vector<int> coupling_of_;  // its coupling with the residual's point, -1 when none
  std::vector<Coupling> couplings_;
  std::vector<int> point_couplings_begin_;
  int num_columns_ = 0;
  int num_points_ = 0;
  int num_parameters_ = 0;
  int max_residuals_ = 0;
  int max_parameters_ = 0;
  int max_block_size_ = 0;
  bool ok_ = false;  // every block the residuals use was declared
  // Normal equations at the current parameters (undamped).
  // The reduced system's blocks (a, b), a <= b: row a's are pair_block_[pair_begin_[a] ..
  // pair_begin_[a + 1]), each column-major tangent_a x tangent_b at pair_offset_.
  int num_column_blocks_ = 0;
  std::vector<int> pair_begin_;
  std::vector<int> pair_block_;
  std::vector<size_t> pair_offset_;
  std::vector<double> s_blocks_;  // J^T J (undamped)
  std::vector<double> work_;      // damped, minus the points' Schur terms
  DenseSchurOptions::Factorization factorization_;
  bool sparse_ = false;
  double fill_ = 0.0;
  Eigen::SparseMatrix<double> sparse_s_;  // upper triangle, pattern fixed at setup
  std::vector<int> pair_value_begin_;     // per block: its columns' entries in value_starts_
  std::vector<int> value_starts_;         // per block column: first index in sparse_s_'s values
  SparseCholesky sparse_llt_;
  Eigen::VectorXd g_c_;
  std::vector<double> w_;
  std::vector<Matrix3> v_;
  std::vector<Eigen::Vector3d> g_p_;
  // The last step.
  std::vector<Matrix3> v_inverse_;
  Eigen::VectorXd delta_c_;
  std::vector<Eigen::Vector3d> delta_p_;
  std::vector<double> point_g_delta_;  // g_p . delta_p
  std::vector<double> point_dDd_;      // delta_p^T D_p delta_p
  double step_g_delta_ = 0.0;          // g . delta of the last step
  double step_dDd_ = 0.0;              // delta^T D delta of the last step
  std::vector<double> backup_;
  // The dogleg's Gauss-Newton step and scaled gradient (KeepGaussNewtonStep).
  Eigen::VectorXd gn_c_, u_c_;
  std::vector<Eigen::Vector3d> gn_p_, u_p_;
  // The parts (kParts): residuals_[residual_part_begin_[k] .. [k + 1]) are points
  // [point_part_begin_[k] .. [k + 1]); rows [row_group_begin_[k] .. [k + 1]) of the reduced
  // system, updated by group_points_[k].
  PartRunner runner_;
  std::vector<int> residual_part_begin_;
  std::vector<int> point_part_begin_;
  std::vector<int> row_group_begin_;
  std::vector<std::vector<int>> group_points_;
  std::array<PartScratch, kParts> parts_;
  std::array<bool, kParts> part_ok_{};
  std::vector<ResidualPair> residual_pairs_;
  std::vector<size_t> compact_of_pair_;  // per block pair: its compact offset (residual pairs)
  std::vector<double> t_;                // W V^-1 per coupling, laid out as w_
  Eigen::VectorXd rhs_;                  // the reduced system's right-hand side
  double seconds_factorise_ = 0.0;       // SolveStep's factorisations, summed
  double squared_norm_ = 0.0;
};

}  // namespace

void SchurProblem::Reserve(size_t num_parameter_blocks, size_t num_residual_blocks,
                           size_t num_parameters) {
  parameter_blocks_.reserve(num_parameter_blocks);
  residual_blocks_.reserve(num_residual_blocks);
  parameters_.reserve(num_parameters);
}

void SchurProblem::AddParameterBlock(double* x, int size, const ceres::Manifold* manifold,
                                     bool constant) {
  parameter_blocks_.push_back({x, size, manifold, constant});
}

void SchurProblem::AddResidualBlock(const ceres::CostFunction* cost,
                                    const ceres::LossFunction* loss, const double* const* blocks,
                                    int count) {
  residual_blocks_.push_back({cost, loss, static_cast<int>(parameters_.size()), count});
  // The solver writes through the blocks of its own parameters (SchurProblem owns nothing).
  for (int i = 0; i < count; ++i) parameters_.push_back(const_cast<double*>(blocks[i]));
}

DenseSchurSummary SolveWithDenseSchur(const DenseSchurOptions& options,
                                      const std::vector<double*>& eliminate,
                                      ceres::Problem* problem) {
  SchurProblem view;
  std::vector<double*> blocks;
  problem->GetParameterBlocks(&blocks);
  for (double* x : blocks)
    view.AddParameterBlock(x, problem->ParameterBlockSize(x), problem->GetManifold(x),
                           problem->IsParameterBlockConstant(x));
  std::vector<ceres::ResidualBlockId> ids;
  problem->GetResidualBlocks(&ids);
  for (const ceres::ResidualBlockId id : ids) {
    problem->GetParameterBlocksForResidualBlock(id, &blocks);
    view.AddResidualBlock(problem->GetCostFunctionForResidualBlock(id),
                          problem->GetLossFunctionForResidualBlock(id), blocks.data(),
                          static_cast<int>(blocks.size()));
  }
  return SolveWithDenseSchur(options, eliminate, view);
}

namespace {

// The tests and bookkeeping both trust-region loops share (Ceres' order and messages).

// Before a step: true when the gradient is small enough or the steps are used up.
bool StopBeforeStep(const DenseSchurOptions& options, const DenseSchurProblem& dense,
                    DenseSchurSummary* summary) {
  if (dense.GradientMaxNorm() <= options.gradient_tolerance) {
    summary->converged = true;
    summary->message = "gradient tolerance reached";
    return true;
  }
  if (summary->successful_steps + summary->unsuccessful_steps >= options.max_iterations) {
    summary->message = "maximum number of iterations reached";
    return true;
  }
  return false;
}

// True (converged) when the step is below the parameter tolerance.
bool StepBelowTolerance(const DenseSchurOptions& options, const DenseSchurProblem& dense,
                        double step_norm, DenseSchurSummary* summary) {
  if (step_norm >
      options.parameter_tolerance * (dense.ParameterNorm() + options.parameter_tolerance))
    return false;
  summary->converged = true;
  summary->message = "parameter tolerance reached";
  return true;
}

// Takes the step set in `dense` and evaluates the cost there; the step stays when it lowers the
// cost by more than kMinRelativeDecrease of the model's decrease, else it is undone.
struct StepTrial {
  bool accepted = false;
  double new_cost = 0.0;
  double rho = 0.0;  // actual over predicted decrease (0 when not evaluated)
};
StepTrial TryStep(DenseSchurProblem* dense, double cost, double model_decrease,
                  DenseSchurSummary* summary) {
  StepTrial trial;
  trial.new_cost = cost;
  if (!(model_decrease > 0.0) || !dense->Step()) return trial;
  const Timer timer;
  const bool evaluated = dense->Evaluate(/*linearise=*/false, &trial.new_cost);
  summary->seconds_residuals += timer.Seconds();
  if (evaluated && std::isfinite(trial.new_cost)) {
    trial.rho = (cost - trial.new_cost) / model_decrease;
    trial.accepted = trial.rho > kMinRelativeDecrease;
  }
  if (!trial.accepted) dense->Restore();
  return trial;
}

// An accepted step: the cost and summary move to it. True when the function tolerance stops.
bool AcceptStep(const DenseSchurOptions& options, const DenseSchurProblem& dense, double new_cost,
                double* cost, DenseSchurSummary* summary) {
  ++summary->successful_steps;
  const double relative_change = (*cost - new_cost) / *cost;
  *cost = new_cost;
  summary->final_cost = new_cost;
  summary->final_squared_norm = dense.squared_norm();
  if (relative_change > options.function_tolerance) return false;
  summary->converged = true;
  summary->message = "function tolerance reached";
  return true;
}

// A rejected step on a radius already below its minimum stops (converged).
bool RadiusBelowMinimum(double radius, DenseSchurSummary* summary) {
  if (radius >= kMinRadius) return false;
  summary->converged = true;
  summary->message = "trust region radius below its minimum";
  return true;
}

// The dogleg iterations (Powell; Ceres' DoglegStrategy, traditional variant): the
// Gauss-Newton step with a small damping mu_gn (raised tenfold while the reduced system is not
// positive definite), the Cauchy point along the scaled gradient, and between them the point of
// the path at the trust-region radius, all in the Jacobi-scaled norm |x|_D. A rejected step
// halves the radius and reuses both steps: no new factorisation, one residual evaluation.
template <typename Linearise>
void Dogleg(const DenseSchurOptions& options, DenseSchurProblem* dense, double* cost,
            const Linearise& linearise, DenseSchurSummary* summary) {
  constexpr double kMinMu = 1e-8, kMaxMu = 1.0;
  constexpr double kMaxExtrapolation = 4.0;
  double radius = options.initial_trust_region_radius;
  double mu = kMinMu;
  bool reuse = false;
  DenseSchurProblem::DoglegTerms t;
  while (true) {
    if (StopBeforeStep(options, *dense, summary)) return;
    if (!reuse) {
      double model_decrease = 0.0, step_norm = 0.0;
      bool solved = false;
      Timer solve_timer;
      for (; mu <= kMaxMu; mu *= 10.0)
        if ((solved = dense->SolveStep(mu, &model_decrease, &step_norm))) break;
      summary->seconds_solve += solve_timer.Seconds();
      if (!solved) {
        summary->message = "the reduced system is not positive definite";
        return;
      }
      t = dense->KeepGaussNewtonStep(mu);
    }
    // The step a p + b u, p the Gauss-Newton step, u = D^-1 g.
    const double gn_norm = std::sqrt(std::max(t.p_D_p, 0.0));
    const double u_norm = std::sqrt(std::max(t.g_u, 0.0));
    const double alpha = t.u_H_u > 0.0 ? t.g_u / t.u_H_u : std::numeric_limits<double>::max();
    double a = 0.0, b = 0.0;
    if (gn_norm <= radius) {
      a = 1.0;
    } else if (u_norm == 0.0 || alpha * u_norm >= radius) {
      b = u_norm > 0.0 ? -radius / u_norm : 0.0;
    } else {
      // q = -alpha u (the Cauchy point), p; |q + beta (p - q)|_D = radius, beta in [0, 1].
      const double qq = alpha * alpha * t.g_u, pq = -alpha * t.g_p, pp = t.p_D_p;
      const double c2 = pp - 2.0 * pq + qq, c1 = 2.0 * (pq - qq), c0 = qq - radius * radius;
      const double disc = std::max(c1 * c1 - 4.0 * c2 * c0, 0.0);
      const double beta = c2 > 0.0 ? (-c1 + std::sqrt(disc)) / (2.0 * c2) : 1.0;
      a = beta;
      b = -alpha * (1.0 - beta);
    }
    // m(a p + b u) = a g.p + b g.u + (a^2 p'Hp + 2 a b u'Hp + b^2 u'Hu) / 2.
    const double pHp = -t.g_p - t.mu * t.p_D_p, uHp = -t.g_u - t.mu * t.g_p;
    const double model_decrease =
        -(a * t.g_p + b * t.g_u + 0.5 * (a * a * pHp + 2.0 * a * b * uHp + b * b * t.u_H_u));
    const double step_scaled =
        std::sqrt(std::max(a * a * t.p_D_p + 2.0 * a * b * t.g_p + b * b * t.g_u, 0.0));
    const double step_norm = dense->SetDoglegStep(a, b);
    if (StepBelowTolerance(options, *dense, step_norm, summary)) return;
    const StepTrial trial = TryStep(dense, *cost, model_decrease, summary);
    const bool accepted = trial.accepted;
    const double rho = trial.rho;
    double new_cost = trial.new_cost;
    // The cost fell well beyond the model's prediction (rho > 1.2): the model's curvature along
    // the step is too high (the Gauss-Newton term drops the residuals' own curvature, and a
    // robust loss flattens), so the step stops short. The parabola through the cost at 0 and 1
    // with the exact slope g.delta there gives a longer step; one residual evaluation tries it.
    // On bench/scale's 1000-image street the final adjustment's Gauss-Newton steps had rho
    // 1.5-2 and each took only ~60 % of the remaining decrease.
    double extrapolation = 1.0;
    if (accepted && rho > 1.2) {
      const double slope = a * t.g_p + b * t.g_u;  // d cost / d lambda at lambda = 0
      const double curvature = (new_cost - *cost) - slope;
      const double lambda = curvature > 0.0
                                ? std::min(-slope / (2.0 * curvature), kMaxExtrapolation)
                                : kMaxExtrapolation;
      if (lambda > 1.5) {
        const Timer timer;
        double extrapolated_cost = new_cost;
        dense->Restore();
        dense->SetDoglegStep(lambda * a, lambda * b);
        bool better = dense->Step() && dense->Evaluate(/*linearise=*/false, &extrapolated_cost) &&
                      std::isfinite(extrapolated_cost) && extrapolated_cost < new_cost;
        if (better) {
          new_cost = extrapolated_cost;
          extrapolation = lambda;
        } else {  // back to the step itself
          dense->Restore();
          dense->SetDoglegStep(a, b);
          if (!dense->Step() || !dense->Evaluate(/*linearise=*/false, &new_cost)) {
            summary->message = "a cost function failed";
            return;
          }
        }
        summary->seconds_residuals += timer.Seconds();
      }
    }
    if (options.progress_to_stdout)
      std::printf(
          "%4d %s cost %.6e change %+.3e step %.3e rho %.3f radius %.3e (dogleg %.2f %.2e, "
          "x %.2f)\n",
          summary->successful_steps + summary->unsuccessful_steps, accepted ? "ok  " : "fail",
          accepted ? new_cost : *cost, *cost - new_cost, step_norm, rho, radius, a, b,
          extrapolation);
    if (!accepted) {
      ++summary->unsuccessful_steps;
      // Half the failed step's length, not only half the radius (Ceres): after a radius
      // increase the failed step is often the Gauss-Newton step well inside it, and halving the
      // radius alone tried a second step nearly as long (Nocedal & Wright, "Numerical
      // optimization", 2006, alg. 4.1 and sec. 4.1, shrink from the step's length). bench/scale's
      // 1000-image final adjustment from one start: 16 -> 13 steps, 6 -> 4 failures, the same
      // minimum (cost within 1e-6); Strecha's adjustments unchanged.
      radius = 0.5 * std::min(radius, step_scaled);
      reuse = true;
      if (RadiusBelowMinimum(radius, summary)) return;
      continue;
    }
    if (rho < 0.25) radius *= 0.5;
    if (rho > 0.75) radius = std::max(radius, 3.0 * extrapolation * step_scaled);
    radius = std::min(radius, kMaxRadius);
    mu = std::max(kMinMu, mu / 5.0);
    reuse = false;
    if (AcceptStep(options, *dense, new_cost, cost, summary)) return;
    if (!linearise()) {
      summary->message = "a cost function failed";
      return;
    }
  }
}

}  // namespace

DenseSchurSummary SolveWithDenseSchur(const DenseSchurOptions& options,
                                      const std::vector<double*>& eliminate,
                                      const SchurProblem& problem) {
  DenseSchurSummary summary;
  Timer timer;
  DenseSchurProblem dense(eliminate, options.factorization, options.num_threads, problem);
  summary.seconds_setup = timer.Seconds();
  if (!dense.ok()) {
    summary.message = "a residual block uses a parameter block the problem does not have";
    return summary;
  }
  summary.sparse = dense.sparse();
  summary.reduced_columns = dense.num_columns();
  summary.reduced_fill = dense.fill();
  double cost = 0.0;
  const auto linearise = [&] {
    const Timer t;
    const bool ok = dense.Evaluate(/*linearise=*/true, &cost);
    summary.seconds_linearise += t.Seconds();
    return ok;
  };
  if (!linearise()) {
    summary.message = "a cost function failed at the initial parameters";
    return summary;
  }
  summary.usable = true;
  summary.initial_cost = summary.final_cost = cost;
  summary.initial_squared_norm = summary.final_squared_norm = dense.squared_norm();
  if (options.strategy == DenseSchurOptions::Strategy::kDogleg) {
    Dogleg(options, &dense, &cost, linearise, &summary);
    summary.seconds_factorise = dense.seconds_factorise();
    return summary;
  }
  double radius = options.initial_trust_region_radius;
  double decrease_factor = 2.0;
  while (true) {
    if (StopBeforeStep(options, dense, &summary)) break;
    const double mu = 1.0 / radius;
    double model_decrease = 0.0, step_norm = 0.0;
    StepTrial trial;
    trial.new_cost = cost;
    Timer solve_timer;
    const bool solved = dense.SolveStep(mu, &model_decrease, &step_norm);
    summary.seconds_solve += solve_timer.Seconds();
    if (solved) {
      if (StepBelowTolerance(options, dense, step_norm, &summary)) break;
      trial = TryStep(&dense, cost, model_decrease, &summary);
      if (trial.accepted)
        radius = std::min(kMaxRadius,
                          radius / std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * trial.rho - 1.0, 3)));
    }
    if (options.progress_to_stdout)
      std::printf("%4d %s cost %.6e change %+.3e step %.3e rho %.3f radius %.3e\n",
                  summary.successful_steps + summary.unsuccessful_steps,
                  trial.accepted ? "ok  " : "fail", trial.accepted ? trial.new_cost : cost,
                  cost - trial.new_cost, step_norm, trial.rho, radius);
    if (!trial.accepted) {
      ++summary.unsuccessful_steps;
      radius /= decrease_factor;
      decrease_factor *= 2.0;
      if (RadiusBelowMinimum(radius, &summary)) break;
      continue;
    }
    decrease_factor = 2.0;
    if (AcceptStep(options, dense, trial.new_cost, &cost, &summary)) break;
    if (!linearise()) {
      summary.message = "a cost function failed";
      break;
    }
  }
  summary.seconds_factorise = dense.seconds_factorise();
  return summary;
}

}  // namespace varsfm
