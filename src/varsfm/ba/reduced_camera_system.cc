#include "varsfm/ba/schur_system.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "varsfm/util/timer.h"

// The reduced camera system S - W V^-1 W^T (Triggs et al., "Bundle adjustment - a modern
// synthesis", 2000, sec. 6.1): its block pattern, fixed at setup, and its solution by Cholesky
// after Jacobi scaling, dense (LAPACK) or sparse (CHOLMOD), cholesky.h.

namespace varsfm {

// The reduced system's block structure: block (a, b), a <= b, exists when a residual or a
// point involves both; each block row is sorted, its diagonal block first. The system is
// factorised sparse when it has many columns and few blocks (a sequence: each image shares
// points with its neighbours only), dense otherwise.
//
// Row a is collected from the residuals and the points that involve a, each partner marked
// once: a point of track length L offers L(L-1)/2 pairs, and on a collection that densifies
// the sum over points of L^2 is far larger than the number of distinct blocks.
void SchurSystem::BuildReducedStructure() {
  num_column_blocks_ = 0;
  while (num_column_blocks_ < static_cast<int>(blocks_.size()) &&
         blocks_[num_column_blocks_].column >= 0)
    ++num_column_blocks_;
  const auto is_column = [&](int block) { return block >= 0 && block < num_column_blocks_; };
  // Per column block: the residuals with another column block (CSR), and the points coupled
  // with it, by their coupling index (CSR, ascending).
  std::vector<int> residual_begin(num_column_blocks_ + 1, 0);
  std::vector<int> coupling_begin(num_column_blocks_ + 1, 0);
  const auto column_blocks_of = [&](const Residual& r) {
    int n = 0;
    for (int i = 0; i < r.count; ++i) n += is_column(block_of_[r.begin + i]) ? 1 : 0;
    return n;
  };
  for (const Residual& r : residuals_)
    if (column_blocks_of(r) >= 2)
      for (int i = 0; i < r.count; ++i)
        if (is_column(block_of_[r.begin + i])) ++residual_begin[block_of_[r.begin + i] + 1];
  for (const Coupling& c : couplings_) ++coupling_begin[c.block + 1];
  for (int a = 0; a < num_column_blocks_; ++a) {
    residual_begin[a + 1] += residual_begin[a];
    coupling_begin[a + 1] += coupling_begin[a];
  }
  std::vector<int> residuals_of(residual_begin.back());
  std::vector<int> couplings_of(coupling_begin.back());
  {
    std::vector<int> next(residual_begin.begin(), residual_begin.end() - 1);
    for (size_t k = 0; k < residuals_.size(); ++k) {
      const Residual& r = residuals_[k];
      if (column_blocks_of(r) < 2) continue;
      for (int i = 0; i < r.count; ++i)
        if (is_column(block_of_[r.begin + i]))
          residuals_of[next[block_of_[r.begin + i]]++] = static_cast<int>(k);
    }
    next.assign(coupling_begin.begin(), coupling_begin.end() - 1);
    for (size_t i = 0; i < couplings_.size(); ++i)
      couplings_of[next[couplings_[i].block]++] = static_cast<int>(i);
  }
  std::vector<int> point_of_coupling(couplings_.size());
  for (int p = 0; p < num_points_; ++p)
    for (int i = point_couplings_begin_[p]; i < point_couplings_begin_[p + 1]; ++i)
      point_of_coupling[i] = p;

  pair_begin_.assign(num_column_blocks_ + 1, 0);
  pair_block_.clear();
  pair_offset_.clear();
  std::vector<int> marked_in_row(num_column_blocks_, -1);
  size_t offset = 0;
  for (int a = 0; a < num_column_blocks_; ++a) {
    pair_begin_[a] = static_cast<int>(pair_block_.size());
    const auto mark = [&](int b) {
      if (b > a && marked_in_row[b] != a) {
        marked_in_row[b] = a;
        pair_block_.push_back(b);
      }
    };
    pair_block_.push_back(a);
    for (int k = residual_begin[a]; k < residual_begin[a + 1]; ++k) {
      const Residual& r = residuals_[residuals_of[k]];
      for (int i = 0; i < r.count; ++i)
        if (is_column(block_of_[r.begin + i])) mark(block_of_[r.begin + i]);
    }
    // A point's couplings are sorted by block: those after a's own are the partners b > a.
    for (int k = coupling_begin[a]; k < coupling_begin[a + 1]; ++k) {
      const int i = couplings_of[k];
      const int p = point_of_coupling[i];
      for (int j = i + 1; j < point_couplings_begin_[p + 1]; ++j) mark(couplings_[j].block);
    }
    std::sort(pair_block_.begin() + pair_begin_[a] + 1, pair_block_.end());
    for (size_t k = pair_begin_[a]; k < pair_block_.size(); ++k) {
      pair_offset_.push_back(offset);
      offset += static_cast<size_t>(blocks_[a].tangent) * blocks_[pair_block_[k]].tangent;
    }
  }
  pair_begin_[num_column_blocks_] = static_cast<int>(pair_block_.size());
  pair_block_.push_back(std::numeric_limits<int>::max());  // sentinel for the row walks
  s_blocks_.assign(offset, 0.0);
  g_c_.resize(num_columns_);
  // Sparse for a large system (beyond 1500 columns, ~170 images, where a dense factorisation
  // costs over a GFLOP an iteration) or a mid-sized one whose blocks fill less than a quarter of
  // it; below that the points' Schur terms dominate the solve either way (docs/mapper.md,
  // "Speed").
  const double upper = 0.5 * static_cast<double>(num_columns_) * (num_columns_ + 1);
  fill_ = upper > 0.0 ? static_cast<double>(offset) / upper : 0.0;
  sparse_ =
      factorization_ == SchurSolverOptions::Factorization::kSparse ||
      (factorization_ == SchurSolverOptions::Factorization::kAuto &&
       (num_columns_ > 1500 || (num_columns_ > 300 && static_cast<double>(offset) < 0.25 * upper)));
  // Beyond iterative_min_blocks_ blocks the system is solved by conjugate gradients
  // (reduced_camera_pcg.cc), which needs no pattern.
  iterative_ = sparse_ && iterative_min_blocks_ > 0 && num_column_blocks_ >= iterative_min_blocks_;
  if (sparse_ && !iterative_) BuildSparsePattern();
}

// The sparse matrix's pattern once (upper triangle, column-major, rows ascending), written
// directly from the block structure: column c of block column b holds, for each block (a, b) in
// ascending a, block a's rows (on the diagonal block only rows up to c). value_starts_ records
// where each block column's run starts, for FillSparse.
void SchurSystem::BuildSparsePattern() {
  const int num_pairs = pair_begin_[num_column_blocks_];
  // The blocks (a, b) of each block column b, by pair index, in ascending a.
  std::vector<int> column_begin(num_column_blocks_ + 1, 0);
  for (int k = 0; k < num_pairs; ++k) ++column_begin[pair_block_[k] + 1];
  for (int b = 0; b < num_column_blocks_; ++b) column_begin[b + 1] += column_begin[b];
  std::vector<int> column_pairs(num_pairs);
  std::vector<int> row_of_pair(num_pairs);
  {
    std::vector<int> next(column_begin.begin(), column_begin.end() - 1);
    for (int a = 0; a < num_column_blocks_; ++a)
      for (int k = pair_begin_[a]; k < pair_begin_[a + 1]; ++k) {
        column_pairs[next[pair_block_[k]]++] = k;
        row_of_pair[k] = a;
      }
  }
  pair_value_begin_.resize(num_pairs);
  int num_starts = 0;
  for (int k = 0; k < num_pairs; ++k) {
    pair_value_begin_[k] = num_starts;
    num_starts += blocks_[pair_block_[k]].tangent;
  }
  value_starts_.assign(num_starts, 0);
  size_t nonzeros = 0;
  for (int b = 0; b < num_column_blocks_; ++b)
    for (int c = 0; c < blocks_[b].tangent; ++c)
      for (int q = column_begin[b]; q < column_begin[b + 1]; ++q) {
        const int a = row_of_pair[column_pairs[q]];
        nonzeros += a == b ? c + 1 : blocks_[a].tangent;
      }
  sparse_s_.resize(num_columns_, num_columns_);
  sparse_s_.resizeNonZeros(static_cast<Eigen::Index>(nonzeros));
  int* outer = sparse_s_.outerIndexPtr();
  int* inner = sparse_s_.innerIndexPtr();
  std::fill_n(sparse_s_.valuePtr(), nonzeros, 1.0);
  int entry = 0;
  for (int b = 0; b < num_column_blocks_; ++b)
    for (int c = 0; c < blocks_[b].tangent; ++c) {
      outer[blocks_[b].column + c] = entry;
      for (int q = column_begin[b]; q < column_begin[b + 1]; ++q) {
        const int k = column_pairs[q];
        const Block& ba = blocks_[row_of_pair[k]];
        value_starts_[pair_value_begin_[k] + c] = entry;
        const int rows = row_of_pair[k] == b ? c + 1 : ba.tangent;
        for (int j = 0; j < rows; ++j) inner[entry++] = ba.column + j;
      }
    }
  outer[num_columns_] = entry;
  sparse_llt_.AnalyzePattern(sparse_s_);
}

// Jacobi scaling of the reduced system (work_, rhs_), then Cholesky of its upper triangle (dense,
// or sparse for a sequence's banded camera graph): delta_c. False when the system is not
// positive definite or the step not finite.
bool SchurSystem::SolveReducedSystem() {
  Eigen::VectorXd scale(num_columns_);
  for (int a = 0; a < num_column_blocks_; ++a) {
    const int ta = blocks_[a].tangent;
    const double* d = &work_[pair_offset_[pair_begin_[a]]];
    for (int i = 0; i < ta; ++i)
      scale[blocks_[a].column + i] = 1.0 / std::sqrt(std::max(d[i * ta + i], 1e-300));
  }
  const Timer factorise;
  const Eigen::VectorXd scaled_rhs = scale.asDiagonal() * rhs_;
  Eigen::VectorXd y;
  if (iterative_) {
    if (!SolveScaledReducedIteratively(scale, scaled_rhs, &y)) return false;
    reduced_residual_ = reduced_residual_.cwiseQuotient(scale);  // back to S delta_c - rhs
  } else if (sparse_) {
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
  return delta_c_.allFinite();
}

// The scaled reduced system (work_) into the sparse matrix's values / a dense upper triangle.
void SchurSystem::FillSparse(const Eigen::VectorXd& scale) {
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

void SchurSystem::FillDense(const Eigen::VectorXd& scale, Eigen::MatrixXd* s) const {
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

}  // namespace varsfm
