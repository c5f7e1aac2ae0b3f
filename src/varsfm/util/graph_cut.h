#pragma once
// A binary labelling by s-t minimum cut with the Boykov-Kolmogorov max-flow algorithm (Boykov &
// Kolmogorov, "An experimental comparison of min-cut/max-flow algorithms for energy minimization
// in vision", PAMI 2004): nodes are labelled source side or sink side so that the summed capacity
// of the edges cut from the source side to the sink side is least. The source side returned is
// the set of nodes reachable from the source in the residual graph of the maximum flow, the
// smallest source side of all minimum cuts, which does not depend on how the flow was found.
//
// Written here rather than taken from Boost.Graph's boykov_kolmogorov_max_flow because that one
// stores every terminal link as a pair of explicit edges with 64-bit descriptors: with it the mesh
// stage of fountain-P11 (a 2-million-tetrahedron cut) peaked at 1.4 GB and a quarter of its
// samples were page faults, most under the cut (bench/results/2026-12-03-min-cut.md). Here terminal
// capacities are one number per node (their common part is pushed at once, as in Kolmogorov's
// maxflow library) and an arc is 16 bytes.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace varsfm {

class MinCut {
 public:
  // `expected_edges`: how many AddEdge calls will follow (a hint: the storage is reserved once).
  explicit MinCut(size_t num_nodes, size_t expected_edges = 0);

  // Capacities source -> node (paid when the node ends on the sink side) and node -> sink (paid
  // when it ends on the source side). Non-negative; calls for one node add up.
  void SetTerminalWeights(size_t node, double source_capacity, double sink_capacity);
  // Capacities a -> b (paid when a is on the source side and b on the sink side) and b -> a.
  // Non-negative; a != b.
  void AddEdge(size_t a, size_t b, double capacity_ab, double capacity_ba);
  // Per node: true when it is on the source side of the minimum cut described above. The flow's
  // value in *flow. Call once.
  std::vector<bool> Solve(double* flow = nullptr);

 private:
  struct Edge {
    uint32_t a, b;
    double capacity_ab, capacity_ba;
  };
  std::vector<double> terminal_;  // source minus sink capacity per node (one per node)
  double terminal_flow_ = 0;      // what the terminal links of a node carry straight through it
  std::vector<Edge> edges_;
};

}  // namespace varsfm
