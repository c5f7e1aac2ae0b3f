#include "varsfm/util/graph_cut.h"

#include <cstdint>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/boykov_kolmogorov_max_flow.hpp>
#pragma GCC diagnostic pop

#include "varsfm/util/error.h"

namespace varsfm {
namespace {

struct RandomGraph {
  size_t num_nodes = 0;
  std::vector<double> source, sink;  // terminal capacities per node
  struct Edge {
    size_t a, b;
    double ab, ba;
  };
  std::vector<Edge> edges;

  MinCut Build() const {
    MinCut cut(num_nodes, edges.size());
    for (size_t i = 0; i < num_nodes; ++i) cut.SetTerminalWeights(i, source[i], sink[i]);
    for (const Edge& e : edges) cut.AddEdge(e.a, e.b, e.ab, e.ba);
    return cut;
  }

  // What a labelling (bit i set: node i on the source side) cuts.
  double CutCost(uint32_t source_side) const {
    double cost = 0;
    for (size_t i = 0; i < num_nodes; ++i) cost += (source_side >> i & 1) ? sink[i] : source[i];
    for (const Edge& e : edges) {
      const bool a = source_side >> e.a & 1, b = source_side >> e.b & 1;
      if (a && !b) cost += e.ab;
      if (b && !a) cost += e.ba;
    }
    return cost;
  }
};

// Small integer capacities (exact in double, many ties), some zero; some nodes linked to both
// terminals, some to none.
RandomGraph MakeRandomGraph(std::mt19937& rng, size_t num_nodes, size_t num_edges) {
  std::uniform_int_distribution<int> capacity(0, 4), node(0, static_cast<int>(num_nodes) - 1);
  RandomGraph g;
  g.num_nodes = num_nodes;
  for (size_t i = 0; i < num_nodes; ++i) {
    g.source.push_back(capacity(rng) > 2 ? capacity(rng) : 0);
    g.sink.push_back(capacity(rng) > 2 ? capacity(rng) : 0);
  }
  while (g.edges.size() < num_edges) {
    const size_t a = node(rng), b = node(rng);
    if (a != b) g.edges.push_back({a, b, double(capacity(rng)), double(capacity(rng))});
  }
  return g;
}

TEST(MinCut, CutsTheCheapestEdges) {
  // source -> 0 (5), 0 -> 1 (1), 1 -> sink (5), 0 -> sink (2), source -> 1 (1): the least cut
  // separates 0 (source side) from 1 (sink side) and pays source -> 1, 0 -> 1 and 0 -> sink: 4.
  MinCut cut(2);
  cut.SetTerminalWeights(0, 5, 2);
  cut.SetTerminalWeights(1, 1, 5);
  cut.AddEdge(0, 1, 1, 0);
  double flow = 0;
  const std::vector<bool> source_side = cut.Solve(&flow);
  EXPECT_DOUBLE_EQ(flow, 4);  // 0 -> sink 2, 0 -> 1 -> sink 1, source -> 1 -> sink 1
  EXPECT_TRUE(source_side[0]);
  EXPECT_FALSE(source_side[1]);
}

TEST(MinCut, TerminalWeightsOfOneNodeAddUp) {
  MinCut once(1), twice(1);
  once.SetTerminalWeights(0, 3, 5);
  twice.SetTerminalWeights(0, 1, 4);
  twice.SetTerminalWeights(0, 2, 1);
  double flow_once = 0, flow_twice = 0;
  EXPECT_EQ(once.Solve(&flow_once), twice.Solve(&flow_twice));
  EXPECT_DOUBLE_EQ(flow_once, 3);
  EXPECT_DOUBLE_EQ(flow_twice, 3);
}

// Every labelling of random graphs of up to 11 nodes enumerated: the flow equals the least cut
// (max-flow min-cut theorem) and the source side is the smallest minimum cut's, i.e. the
// intersection of the source sides of all minimum cuts.
TEST(MinCut, FindsTheSmallestMinimumCutOfEveryRandomGraph) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 400; ++trial) {
    const size_t n = 1 + trial % 11;
    const RandomGraph g = MakeRandomGraph(rng, n, n > 1 ? (trial * 7) % (3 * n + 1) : 0);
    double least = 1e300;
    for (uint32_t s = 0; s < (1u << n); ++s) least = std::min(least, g.CutCost(s));
    uint32_t smallest = (1u << n) - 1;
    for (uint32_t s = 0; s < (1u << n); ++s)
      if (g.CutCost(s) == least) smallest &= s;
    ASSERT_EQ(g.CutCost(smallest), least) << "trial " << trial;  // min cuts form a lattice
    MinCut cut = g.Build();
    double flow = -1;
    const std::vector<bool> side = cut.Solve(&flow);
    EXPECT_DOUBLE_EQ(flow, least) << "trial " << trial;
    for (size_t i = 0; i < n; ++i)
      EXPECT_EQ(side[i], bool(smallest >> i & 1)) << "trial " << trial << " node " << i;
  }
}

// Grids of the size of texture labelling problems, with real-valued capacities: the same flow
// and the same labelling as Boost.Graph's implementation of the same algorithm.
TEST(MinCut, AgreesWithBoostOnLargeGrids) {
  using Traits = boost::adjacency_list_traits<boost::vecS, boost::vecS, boost::directedS>;
  using Graph = boost::adjacency_list<
      boost::vecS, boost::vecS, boost::directedS,
      boost::property<
          boost::vertex_color_t, boost::default_color_type,
          boost::property<boost::vertex_distance_t, long,
                          boost::property<boost::vertex_predecessor_t, Traits::edge_descriptor>>>,
      boost::property<
          boost::edge_capacity_t, double,
          boost::property<boost::edge_residual_capacity_t, double,
                          boost::property<boost::edge_reverse_t, Traits::edge_descriptor>>>>;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int trial = 0; trial < 6; ++trial) {
    const int w = 40 + 10 * trial, h = 30 + 5 * trial, n = w * h;
    Graph bg(n + 2);
    auto capacity = boost::get(boost::edge_capacity, bg);
    auto reverse = boost::get(boost::edge_reverse, bg);
    const auto add = [&](int a, int b, double ab, double ba) {
      const auto e = boost::add_edge(a, b, bg).first, r = boost::add_edge(b, a, bg).first;
      capacity[e] = ab, capacity[r] = ba, reverse[e] = r, reverse[r] = e;
    };
    MinCut cut(n);
    for (int i = 0; i < n; ++i) {
      // Unary terms of a smooth random field, so the cut has regions, not noise.
      const double x = i % w, y = i / w;
      const double field = std::sin(0.2 * x + trial) * std::cos(0.15 * y) + 0.3 * (unit(rng) - 0.5);
      const double s = field > 0 ? field : 0.1 * unit(rng),
                   t = field < 0 ? -field : 0.1 * unit(rng);
      cut.SetTerminalWeights(i, s, t);
      add(n, i, s, 0);
      add(i, n + 1, t, 0);
      for (const int j : {i + 1, i + w}) {
        if ((j == i + 1 && (i + 1) % w == 0) || j >= n) continue;
        const double ab = 0.3 * unit(rng), ba = 0.3 * unit(rng);
        cut.AddEdge(i, j, ab, ba);
        add(i, j, ab, ba);
      }
    }
    const double boost_flow = boost::boykov_kolmogorov_max_flow(bg, n, n + 1);
    const auto color = boost::get(boost::vertex_color, bg);
    double flow = 0;
    const std::vector<bool> side = cut.Solve(&flow);
    EXPECT_NEAR(flow, boost_flow, 1e-9 * boost_flow) << "trial " << trial;
    int differ = 0, on_source = 0;
    for (int i = 0; i < n; ++i) {
      differ += side[i] != (color[i] == boost::black_color);
      on_source += side[i];
    }
    EXPECT_EQ(differ, 0) << "trial " << trial;
    EXPECT_GT(on_source, n / 5) << "trial " << trial;  // a real partition, not a trivial one
    EXPECT_LT(on_source, 4 * n / 5) << "trial " << trial;
  }
}

TEST(MinCut, RefusesBadInput) {
  MinCut cut(3);
  EXPECT_THROW(cut.SetTerminalWeights(0, -1, 0), Error);
  EXPECT_THROW(cut.SetTerminalWeights(3, 1, 0), Error);
  EXPECT_THROW(cut.AddEdge(0, 1, 1, -2), Error);
  EXPECT_THROW(cut.AddEdge(1, 1, 1, 1), Error);
  EXPECT_THROW(cut.AddEdge(0, 3, 1, 1), Error);
}

TEST(MinCut, NodesWithoutLinksAreOnTheSinkSide) {
  MinCut cut(3);
  cut.SetTerminalWeights(0, 2, 0);
  cut.AddEdge(0, 1, 1, 0);  // 1 is reached from the source through 0; 2 from nowhere
  double flow = -1;
  EXPECT_EQ(cut.Solve(&flow), (std::vector<bool>{true, true, false}));
  EXPECT_DOUBLE_EQ(flow, 0);
}

}  // namespace
}  // namespace varsfm
