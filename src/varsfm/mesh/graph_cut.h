#pragma once
// A binary labelling by s-t minimum cut (Boykov & Kolmogorov, "An experimental comparison of
// min-cut/max-flow algorithms for energy minimization in vision", PAMI 2004, through
// Boost.Graph's boykov_kolmogorov_max_flow): nodes are labelled source side or sink side so that
// the summed capacity of the edges cut from the source side to the sink side is least.
#include <cstddef>
#include <memory>
#include <vector>

namespace varsfm {

class MinCut {
 public:
  explicit MinCut(size_t num_nodes);
  ~MinCut();
  MinCut(const MinCut&) = delete;
  MinCut& operator=(const MinCut&) = delete;

  // Capacities source -> node (paid when the node ends on the sink side) and node -> sink (paid
  // when it ends on the source side). Non-negative; call at most once per node.
  void SetTerminalWeights(size_t node, double source_capacity, double sink_capacity);
  // Capacities a -> b (paid when a is on the source side and b on the sink side) and b -> a.
  // Non-negative; a != b.
  void AddEdge(size_t a, size_t b, double capacity_ab, double capacity_ba);
  // Per node: true when it is on the source side of a minimum cut. The flow's value in *flow.
  std::vector<bool> Solve(double* flow = nullptr);

 private:
  struct Graph;
  std::unique_ptr<Graph> graph_;
};

}  // namespace varsfm
