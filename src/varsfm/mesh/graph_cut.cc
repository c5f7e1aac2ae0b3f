#include "varsfm/mesh/graph_cut.h"

// GCC 12 warns of a maybe-uninitialised optional inside Boost's edge iterator.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/boykov_kolmogorov_max_flow.hpp>
#pragma GCC diagnostic pop

#include "varsfm/util/error.h"

namespace varsfm {

// Boost's layout for the algorithm: every edge stores its capacity, residual capacity and the
// edge in the opposite direction.
struct MinCut::Graph {
  using Traits = boost::adjacency_list_traits<boost::vecS, boost::vecS, boost::directedS>;
  using Adjacency = boost::adjacency_list<
      boost::vecS, boost::vecS, boost::directedS,
      boost::property<
          boost::vertex_color_t, boost::default_color_type,
          boost::property<boost::vertex_distance_t, long,
                          boost::property<boost::vertex_predecessor_t, Traits::edge_descriptor>>>,
      boost::property<
          boost::edge_capacity_t, double,
          boost::property<boost::edge_residual_capacity_t, double,
                          boost::property<boost::edge_reverse_t, Traits::edge_descriptor>>>>;
  Adjacency adjacency;
  size_t source = 0, sink = 0;

  void AddPair(size_t a, size_t b, double capacity_ab, double capacity_ba) {
    auto capacity = boost::get(boost::edge_capacity, adjacency);
    auto reverse = boost::get(boost::edge_reverse, adjacency);
    const auto ab = boost::add_edge(a, b, adjacency).first;
    const auto ba = boost::add_edge(b, a, adjacency).first;
    capacity[ab] = capacity_ab;
    capacity[ba] = capacity_ba;
    reverse[ab] = ba;
    reverse[ba] = ab;
  }
};

MinCut::MinCut(size_t num_nodes) : graph_(std::make_unique<Graph>()) {
  graph_->adjacency = Graph::Adjacency(num_nodes + 2);
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
  Graph& g = *graph_;
  const double value = boost::boykov_kolmogorov_max_flow(g.adjacency, g.source, g.sink);
  if (flow) *flow = value;
  // After the flow, the nodes the source's search tree reaches are black; the rest belong to
  // the sink's side of the cut.
  auto color = boost::get(boost::vertex_color, g.adjacency);
  std::vector<bool> source_side(g.source);
  for (size_t i = 0; i < g.source; ++i) source_side[i] = color[i] == boost::black_color;
  return source_side;
}

}  // namespace varsfm
