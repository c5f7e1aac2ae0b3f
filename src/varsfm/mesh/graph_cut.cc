#include "varsfm/mesh/graph_cut.h"

#include <utility>

// GCC 12 warns of a maybe-uninitialised optional inside Boost's edge iterator.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <boost/graph/boykov_kolmogorov_max_flow.hpp>
#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <boost/property_map/property_map.hpp>
#pragma GCC diagnostic pop

#include "varsfm/util/error.h"

namespace varsfm {

// The edges as added, each pair (a -> b, b -> a) consecutive; Solve() lays them out as a
// compressed sparse row graph with the per-edge data in flat arrays. The max-flow then allocates
// nothing per edge (an adjacency_list grows one vector per vertex and frees them all again, which
// cost about a third of texturing's time in view selection's many cuts).
struct MinCut::Graph {
  size_t num_vertices = 0, source = 0, sink = 0;
  std::vector<std::pair<size_t, size_t>> edges;  // (from, to), in the order added
  std::vector<double> capacities;

  void AddPair(size_t a, size_t b, double capacity_ab, double capacity_ba) {
    edges.emplace_back(a, b);
    edges.emplace_back(b, a);
    capacities.push_back(capacity_ab);
    capacities.push_back(capacity_ba);
  }
};

MinCut::MinCut(size_t num_nodes) : graph_(std::make_unique<Graph>()) {
  graph_->num_vertices = num_nodes + 2;
  graph_->source = num_nodes;
  graph_->sink = num_nodes + 1;
}

MinCut::~MinCut() = default;

void MinCut::SetTerminalWeights(size_t node, double source_capacity, double sink_capacity) {
  if (!(source_capacity >= 0 && sink_capacity >= 0)) Fail("min cut: negative terminal weight");
  if (source_capacity > 0) graph_->AddPair(graph_->source, node, source_capacity, 0);
  if (sink_capacity > 0) graph_->AddPair(node, graph_->sink, sink_capacity, 0);
}

void MinCut::AddEdge(size_t a, size_t b, double capacity_ab, double capacity_ba) {
  if (!(capacity_ab >= 0 && capacity_ba >= 0)) Fail("min cut: negative capacity");
  graph_->AddPair(a, b, capacity_ab, capacity_ba);
}

std::vector<bool> MinCut::Solve(double* flow) {
  using Csr = boost::compressed_sparse_row_graph<boost::directedS>;
  using Edge = Csr::edge_descriptor;
  const Graph& g = *graph_;
  const size_t num_edges = g.edges.size();

  // A stable counting sort by the edge's tail: each vertex's out-edges stay in the order they
  // were added, which is the order the max-flow's searches visit them in, so the cut found (among
  // equal ones) does not depend on the graph's layout.
  std::vector<size_t> start(g.num_vertices + 1, 0);
  for (const auto& [from, to] : g.edges) ++start[from + 1];
  for (size_t v = 0; v < g.num_vertices; ++v) start[v + 1] += start[v];
  std::vector<size_t> slot(num_edges);  // the sorted position of the e-th edge added
  {
    std::vector<size_t> next(start.begin(), start.end() - 1);
    for (size_t e = 0; e < num_edges; ++e) slot[e] = next[g.edges[e].first]++;
  }
  std::vector<std::pair<size_t, size_t>> sorted(num_edges);
  std::vector<double> capacity(num_edges);
  for (size_t e = 0; e < num_edges; ++e) {
    sorted[slot[e]] = g.edges[e];
    capacity[slot[e]] = g.capacities[e];
  }
  const Csr csr(boost::edges_are_sorted, sorted.begin(), sorted.end(), g.num_vertices);
  std::vector<Edge> reverse(num_edges);
  for (size_t e = 0; e < num_edges; ++e) {
    const size_t pair = e ^ 1;  // the edges of a pair were added one after the other
    reverse[slot[e]] = Edge(g.edges[pair].first, slot[pair]);
  }

  const auto edge_index = boost::get(boost::edge_index, csr);
  const auto vertex_index = boost::get(boost::vertex_index, csr);
  std::vector<double> residual(num_edges);
  std::vector<Edge> predecessor(g.num_vertices);
  std::vector<boost::default_color_type> color(g.num_vertices);
  std::vector<long> distance(g.num_vertices);
  const double value = boost::boykov_kolmogorov_max_flow(
      csr, boost::make_iterator_property_map(capacity.begin(), edge_index),
      boost::make_iterator_property_map(residual.begin(), edge_index),
      boost::make_iterator_property_map(reverse.begin(), edge_index),
      boost::make_iterator_property_map(predecessor.begin(), vertex_index),
      boost::make_iterator_property_map(color.begin(), vertex_index),
      boost::make_iterator_property_map(distance.begin(), vertex_index), vertex_index, g.source,
      g.sink);
  if (flow) *flow = value;
  // After the flow, the nodes the source's search tree reaches are black; the rest belong to
  // the sink's side of the cut.
  std::vector<bool> source_side(g.source);
  for (size_t i = 0; i < g.source; ++i) source_side[i] = color[i] == boost::black_color;
  return source_side;
}

}  // namespace varsfm
