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
void SchurSystem::BuildReducedStructure() {
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

// The sparse matrix's pattern once (upper triangle, column-major); each block column is a
// contiguous run of its column's non-zeros, recorded in value_starts_ for FillSparse.
void SchurSystem::BuildSparsePattern() {
  // The pattern once (upper triangle, column-major); each block column is a contiguous run of
  // its column's non-zeros, recorded in value_starts_ for FillSparse.
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(s_blocks_.size());
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
        starts.push_back(static_cast<int>(
            std::lower_bound(rows_begin, rows_end, blocks_[a].column) - sparse_s_.innerIndexPtr()));
      }
    }
  value_starts_ = std::move(starts);
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
