#pragma once
// Multi-label Potts energy minimisation by alpha-expansion (Boykov, Veksler & Zabih, "Fast
// approximate energy minimization via graph cuts", PAMI 2001): each move lets every node either
// keep its label or switch to one label alpha, and the best such move is a minimum s-t cut
// (Kolmogorov & Zabih, "What energy functions can be minimized via graph cuts?", PAMI 2004),
// found with the Boykov-Kolmogorov max-flow of util/graph_cut.h. For the Potts model the result is
// within a factor 2 of the global minimum; with two labels it is the global minimum.
#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace varsfm {

// E(labels) = sum_n data(n, label_n) + potts x #{neighbouring pairs with different labels}.
// A node's candidates are the labels it may take, each with its data cost; a node without
// candidates keeps label -1 and has no smoothness term with its neighbours.
struct PottsProblem {
  int num_labels = 0;
  // Candidates of node n: candidate_labels / candidate_costs [offsets[n], offsets[n + 1]).
  std::vector<std::size_t> offsets = {0};
  std::vector<int> candidate_labels;
  std::vector<float> candidate_costs;
  std::vector<std::array<int, 3>> neighbours;  // per node; -1: none
  double potts = 1.0;

  std::size_t num_nodes() const { return offsets.size() - 1; }
  // The data cost of `label` at node n, or a negative value when it is not a candidate.
  float Cost(std::size_t n, int label) const;
};

double PottsEnergy(const PottsProblem& problem, const std::vector<int>& labels);

// Starts from `labels` (each a candidate of its node, or -1 for nodes without candidates) and
// expands every label in turn, in a fixed order, until a whole cycle lowers the energy by at most
// `tolerance` x the energy before it or `max_cycles` are done. Deterministic. A non-empty
// `progress_label` shows the moves' progress under that label.
void ExpandLabels(const PottsProblem& problem, int max_cycles, std::vector<int>* labels,
                  double tolerance, const std::string& progress_label = "");

}  // namespace varsfm
