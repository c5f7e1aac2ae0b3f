#include "varsfm/texture/alpha_expansion.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "varsfm/util/graph_cut.h"
#include "varsfm/util/progress.h"

namespace varsfm {
namespace {

// One alpha-expansion move. Binary variable x_n per movable node: 0 keeps its label, 1 takes
// alpha. A pairwise term E(x_p, x_q) with values A = E(0,0), B = E(0,1), C = E(1,0), D = E(1,1)
// is A + (C - A) x_p + (D - C) x_q + (B + C - A - D)(1 - x_p) x_q (Kolmogorov & Zabih, sec. 4):
// two unary terms and one edge p -> q, cut when p stays on the source side (x_p = 0) and q goes
// to the sink side (x_q = 1). Returns whether any node changed.
//
// Only the nodes with alpha among their candidates can move (`nodes_of_alpha`, ascending), so a
// move costs what they do, not a pass over every node: with a label per photo, passes over
// every node for every label grew with the photos times the faces. `vertex_of` (one entry per
// node, -1 outside the move) is shared by the moves and left all -1.
bool ExpandOne(const PottsProblem& problem, int alpha, const std::vector<size_t>& nodes_of_alpha,
               std::vector<long>* vertex_of_nodes, std::vector<int>* labels_in_out) {
  std::vector<int>& labels = *labels_in_out;
  std::vector<long>& vertex_of = *vertex_of_nodes;
  std::vector<size_t> movable;
  for (const size_t i : nodes_of_alpha) {
    if (labels[i] >= 0 && labels[i] != alpha) {
      vertex_of[i] = static_cast<long>(movable.size());
      movable.push_back(i);
    }
  }
  if (movable.empty()) return false;
  const double w = problem.potts;
  MinCut cut(movable.size());
  std::vector<double> cost_keep(movable.size()), cost_alpha(movable.size());
  for (size_t k = 0; k < movable.size(); ++k) {
    const size_t i = movable[k];
    cost_keep[k] += problem.Cost(i, labels[i]);
    cost_alpha[k] += problem.Cost(i, alpha);
    for (const int j : problem.neighbours[i]) {
      if (j < 0 || labels[j] < 0) continue;
      if (vertex_of[j] < 0) {  // fixed neighbour: a unary term
        cost_keep[k] += labels[j] != labels[i] ? w : 0;
        cost_alpha[k] += labels[j] != alpha ? w : 0;
      } else if (static_cast<size_t>(j) > i) {  // each movable pair once
        const double a = labels[i] != labels[j] ? w : 0, b = w, c = w, d = 0;
        cost_alpha[k] += c - a;
        cost_alpha[vertex_of[j]] += d - c;
        cut.AddEdge(k, vertex_of[j], b + c - a - d, 0);
      }
    }
  }
  for (size_t k = 0; k < movable.size(); ++k) {
    const double diff = cost_alpha[k] - cost_keep[k];
    // Source side keeps the label: a positive difference is paid when k takes alpha.
    if (diff > 0)
      cut.SetTerminalWeights(k, diff, 0);
    else if (diff < 0)
      cut.SetTerminalWeights(k, 0, -diff);
  }
  const std::vector<bool> keeps = cut.Solve();
  bool changed = false;
  for (size_t k = 0; k < movable.size(); ++k) {
    vertex_of[movable[k]] = -1;
    if (!keeps[k]) {
      labels[movable[k]] = alpha;
      changed = true;
    }
  }
  return changed;
}

}  // namespace

float PottsProblem::Cost(size_t n, int label) const {
  for (size_t c = offsets[n]; c < offsets[n + 1]; ++c)
    if (candidate_labels[c] == label) return candidate_costs[c];
  return -1.0f;
}

double PottsEnergy(const PottsProblem& problem, const std::vector<int>& labels) {
  double energy = 0;
  for (size_t i = 0; i < problem.num_nodes(); ++i) {
    if (labels[i] < 0) continue;
    energy += problem.Cost(i, labels[i]);
    for (const int j : problem.neighbours[i])
      if (j > static_cast<int>(i) && labels[j] >= 0 && labels[j] != labels[i])
        energy += problem.potts;
  }
  return energy;
}

void ExpandLabels(const PottsProblem& problem, int max_cycles, std::vector<int>* labels,
                  double tolerance, const std::string& progress_label) {
  // Per label, the nodes that have it among their candidates (Cost >= 0), in node order.
  std::vector<std::vector<size_t>> nodes_of(problem.num_labels);
  for (size_t i = 0; i < problem.num_nodes(); ++i)
    for (size_t c = problem.offsets[i]; c < problem.offsets[i + 1]; ++c) {
      const int label = problem.candidate_labels[c];
      const auto first = problem.candidate_labels.begin() + problem.offsets[i];
      if (std::find(first, problem.candidate_labels.begin() + c, label) ==
              problem.candidate_labels.begin() + c &&
          problem.candidate_costs[c] >= 0)
        nodes_of[label].push_back(i);
    }
  std::vector<long> vertex_of(problem.num_nodes(), -1);
  std::optional<Progress> progress;
  if (!progress_label.empty())
    progress.emplace(progress_label, static_cast<size_t>(max_cycles) * problem.num_labels);
  double energy = PottsEnergy(problem, *labels);
  for (int cycle = 0; cycle < max_cycles; ++cycle) {
    for (int alpha = 0; alpha < problem.num_labels; ++alpha) {
      ExpandOne(problem, alpha, nodes_of[alpha], &vertex_of, labels);
      if (progress) progress->Tick(1, fmt::format("cycle {}", cycle + 1));
    }
    const double after = PottsEnergy(problem, *labels);
    const bool converged = energy - after <= tolerance * std::abs(energy);
    energy = after;
    if (converged) {
      // The cycles left are not needed.
      if (progress)
        progress->Tick(static_cast<size_t>(max_cycles - 1 - cycle) * problem.num_labels,
                       fmt::format("converged in {} cycles", cycle + 1));
      break;
    }
  }
}

}  // namespace varsfm
