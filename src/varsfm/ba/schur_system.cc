#include "varsfm/ba/schur_system.h"

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

// The structure of the Schur system, built once per solve: which blocks are variable, which are
// eliminated, how points couple to the reduced system's blocks, and how the work is cut into
// parts (part_runner.h).

namespace varsfm {

SchurSystem::SchurSystem(const std::vector<double*>& eliminate, const SchurSolverOptions& options,
                         const LeastSquaresProblem& problem)
    : values_(problem.parameters()),
      factorization_(options.factorization),
      iterative_min_blocks_(options.iterative_min_blocks),
      iterative_tolerance_(options.iterative_tolerance),
      iterative_max_iterations_(options.iterative_max_iterations),
      runner_(options.num_threads) {
  residuals_.resize(problem.residual_blocks().size());
  for (size_t i = 0; i < residuals_.size(); ++i) {
    const LeastSquaresProblem::ResidualBlock& block = problem.residual_blocks()[i];
    Residual& r = residuals_[i];
    r.cost = block.cost;
    r.loss = block.loss;
    r.begin = block.begin;
    r.count = block.count;
    max_residuals_ = std::max(max_residuals_, r.cost->num_residuals());
    max_parameters_ = std::max(max_parameters_, r.count);
  }
  if (!BuildBlocks(eliminate, problem)) return;
  BuildCouplings();
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

// False when a residual uses a block the problem does not declare.
bool SchurSystem::BuildBlocks(const std::vector<double*>& eliminate,
                              const LeastSquaresProblem& problem) {
  // The distinct parameter blocks the residuals use, in address order; the variable ones
  // become blocks: columns first, then points.
  std::vector<LeastSquaresProblem::ParameterBlock> declared(problem.parameter_blocks());
  const auto by_address = [](const LeastSquaresProblem::ParameterBlock& a,
                             const LeastSquaresProblem::ParameterBlock& b) { return a.x < b.x; };
  std::sort(declared.begin(), declared.end(), by_address);
  std::vector<double*> sorted_eliminate(eliminate);
  std::sort(sorted_eliminate.begin(), sorted_eliminate.end());
  std::vector<double*> distinct(values_);
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  std::vector<const LeastSquaresProblem::ParameterBlock*> info(distinct.size());
  for (size_t i = 0; i < distinct.size(); ++i) {
    const auto it = std::lower_bound(declared.begin(), declared.end(),
                                     LeastSquaresProblem::ParameterBlock{distinct[i]}, by_address);
    if (it == declared.end() || it->x != distinct[i]) return false;
    info[i] = &*it;
  }
  std::vector<int> block_of_distinct(distinct.size(), -1);
  for (const bool points : {false, true}) {
    for (size_t i = 0; i < distinct.size(); ++i) {
      double* x = distinct[i];
      const LeastSquaresProblem::ParameterBlock& declared_block = *info[i];
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
  return true;
}

// The couplings (point, block), grouped by point and in column order within a point, with W's
// storage.
void SchurSystem::BuildCouplings() {
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
    point_couplings_begin_[p] = std::min(point_couplings_begin_[p], point_couplings_begin_[p + 1]);
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
}

// Cuts the residuals into kParts runs of whole points (each point's residuals in one part,
// about as many residuals in each part), residuals without a point spread by their index.
// Within a part the residuals come point by point (those without a point first), each point's
// in their order in the problem.
void SchurSystem::PartitionResiduals() {
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
               ? std::min(kParts - 1, static_cast<int>(static_cast<int64_t>(per_point[p]) * kParts /
                                                       with_points))
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
void SchurSystem::BuildResidualPairs() {
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
      const size_t size = static_cast<size_t>(blocks_[a].tangent) * blocks_[pair_block_[k]].tangent;
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
void SchurSystem::BuildRowGroups() {
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

}  // namespace varsfm
