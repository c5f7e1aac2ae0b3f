#include "varsfm/util/graph_cut.h"

#include <algorithm>
#include <limits>
#include <utility>

#include "varsfm/util/error.h"

namespace varsfm {
namespace {

// Parent links of the search trees: the arc from a node towards its tree's root, or these.
constexpr uint32_t kFree = std::numeric_limits<uint32_t>::max();  // in no tree
constexpr uint32_t kTerminal = kFree - 1;                         // linked to its terminal
constexpr uint32_t kOrphan = kFree - 2;                           // lost its parent link
constexpr uint32_t kInfiniteDistance = std::numeric_limits<uint32_t>::max();

// The residual graph in compressed sparse row form (each node's arcs contiguous, in the order
// their edges were added) and the two search trees of Boykov & Kolmogorov (section 3): the source
// tree S grows along arcs with residual capacity away from the source, the sink tree T along arcs
// with residual capacity towards the sink; an arc from S to T is an augmenting path. After an
// augmentation the nodes whose parent arc saturated become orphans, which look for a new parent
// in their tree (the "adoption" stage) or become free. Nodes carry the time stamp and distance of
// the paper's section 3.3 heuristics, so an orphan prefers the shortest valid origin.
class BoykovKolmogorov {
 public:
  BoykovKolmogorov(std::vector<uint32_t> first, std::vector<uint32_t> head,
                   std::vector<uint32_t> sister, std::vector<double> capacity,
                   std::vector<double> terminal)
      : first_(std::move(first)),
        head_(std::move(head)),
        sister_(std::move(sister)),
        capacity_(std::move(capacity)),
        terminal_(std::move(terminal)) {
    const size_t n = terminal_.size();
    parent_.assign(n, kFree);
    time_.assign(n, 0);
    distance_.assign(n, 0);
    sink_.assign(n, 0);
    active_.assign(n, 0);
    for (uint32_t i = 0; i < n; ++i) {
      if (terminal_[i] == 0) continue;
      sink_[i] = terminal_[i] < 0;
      parent_[i] = kTerminal;
      distance_[i] = 1;
      SetActive(i);
    }
  }

  // The maximum flow (beyond what the terminal links carry straight through their node).
  double Run() {
    double flow = 0;
    uint32_t current = kFree;  // the node that found the last path grows on first
    while (true) {
      uint32_t i = current;
      if (i != kFree) {
        active_[i] = 0;
        if (parent_[i] == kFree) i = kFree;
      }
      if (i == kFree && (i = NextActive()) == kFree) break;
      const uint32_t join = Grow(i);
      ++now_;
      if (join == kFree) {
        current = kFree;
        continue;
      }
      active_[i] = 1;  // kept out of the queue while it is the current node
      current = i;
      flow += Augment(join);
      for (size_t k = 0; k < orphans_.size(); ++k) Adopt(orphans_[k]);
      orphans_.clear();
    }
    return flow;
  }

  bool InSourceTree(uint32_t i) const { return parent_[i] != kFree && !sink_[i]; }

 private:
  uint32_t Tail(uint32_t arc) const { return head_[sister_[arc]]; }

  // Whether `arc` out of a node of the tree `sink` can carry that tree's flow: away from the
  // source in S, towards the sink in T.
  bool TreeArcOpen(uint32_t arc, bool sink) const {
    return (sink ? capacity_[sister_[arc]] : capacity_[arc]) > 0;
  }

  void SetActive(uint32_t i) {
    if (active_[i]) return;
    active_[i] = 1;
    queue_next_.push_back(i);
  }

  uint32_t NextActive() {
    while (true) {
      if (queue_position_ == queue_.size()) {
        if (queue_next_.empty()) return kFree;
        queue_.swap(queue_next_);
        queue_next_.clear();
        queue_position_ = 0;
      }
      const uint32_t i = queue_[queue_position_++];
      active_[i] = 0;
      if (parent_[i] != kFree) return i;
    }
  }

  // Grows the tree of active node i by its free neighbours; returns the arc from S to T where
  // the trees touch, or kFree.
  uint32_t Grow(uint32_t i) {
    const bool sink = sink_[i];
    for (uint32_t a = first_[i]; a < first_[i + 1]; ++a) {
      if (!TreeArcOpen(a, sink)) continue;
      const uint32_t j = head_[a];
      if (parent_[j] == kFree) {
        sink_[j] = sink;
        Link(j, sister_[a], i);
        SetActive(j);
      } else if (sink_[j] != sink) {
        return sink ? sister_[a] : a;
      } else if (time_[j] <= time_[i] && distance_[j] > distance_[i]) {
        Link(j, sister_[a], i);  // a shorter way to the terminal
      }
    }
    return kFree;
  }

  void Link(uint32_t child, uint32_t arc, uint32_t parent) {
    parent_[child] = arc;
    time_[child] = time_[parent];
    distance_[child] = distance_[parent] + 1;
  }

  void MakeOrphan(uint32_t i) {
    parent_[i] = kOrphan;
    orphans_.push_back(i);
  }

  // Pushes the bottleneck along source -> ... -> Tail(join) -> head(join) -> ... -> sink.
  double Augment(uint32_t join) {
    double bottleneck = capacity_[join];
    for (uint32_t i = Tail(join);;) {
      const uint32_t p = parent_[i];
      if (p == kTerminal) {
        bottleneck = std::min(bottleneck, terminal_[i]);
        break;
      }
      bottleneck = std::min(bottleneck, capacity_[sister_[p]]);
      i = head_[p];
    }
    for (uint32_t i = head_[join];;) {
      const uint32_t p = parent_[i];
      if (p == kTerminal) {
        bottleneck = std::min(bottleneck, -terminal_[i]);
        break;
      }
      bottleneck = std::min(bottleneck, capacity_[p]);
      i = head_[p];
    }
    capacity_[sister_[join]] += bottleneck;
    capacity_[join] -= bottleneck;
    for (uint32_t i = Tail(join);;) {
      const uint32_t p = parent_[i];
      if (p == kTerminal) {
        terminal_[i] -= bottleneck;
        if (terminal_[i] == 0) MakeOrphan(i);
        break;
      }
      capacity_[p] += bottleneck;
      capacity_[sister_[p]] -= bottleneck;
      if (capacity_[sister_[p]] == 0) MakeOrphan(i);
      i = head_[p];
    }
    for (uint32_t i = head_[join];;) {
      const uint32_t p = parent_[i];
      if (p == kTerminal) {
        terminal_[i] += bottleneck;
        if (terminal_[i] == 0) MakeOrphan(i);
        break;
      }
      capacity_[sister_[p]] += bottleneck;
      capacity_[p] -= bottleneck;
      if (capacity_[p] == 0) MakeOrphan(i);
      i = head_[p];
    }
    return bottleneck;
  }

  // Distance from j to its tree's terminal along parent links, or kInfiniteDistance when the
  // way passes an orphan; the nodes on a valid way are stamped with the current time.
  uint32_t Origin(uint32_t j) {
    uint32_t d = 0;
    for (uint32_t k = j;;) {
      if (time_[k] == now_) {
        d += distance_[k];
        break;
      }
      const uint32_t p = parent_[k];
      ++d;
      if (p == kTerminal) {
        time_[k] = now_;
        distance_[k] = 1;
        break;
      }
      if (p == kOrphan) return kInfiniteDistance;
      k = head_[p];
    }
    for (uint32_t k = j, dk = d; time_[k] != now_; k = head_[parent_[k]], --dk) {
      time_[k] = now_;
      distance_[k] = dk;
    }
    return d;
  }

  void Adopt(uint32_t i) {
    const bool sink = sink_[i];
    uint32_t best_arc = kFree, best_distance = kInfiniteDistance;
    for (uint32_t a = first_[i]; a < first_[i + 1]; ++a) {
      // A parent j in i's tree with residual capacity on the arc between them, in the tree's
      // direction (j -> i in S, i -> j in T).
      if (!TreeArcOpen(sister_[a], sink)) continue;
      const uint32_t j = head_[a];
      if (sink_[j] != sink || parent_[j] == kFree) continue;
      const uint32_t d = Origin(j);
      if (d < best_distance) best_arc = a, best_distance = d;
    }
    if (best_arc != kFree) {
      parent_[i] = best_arc;
      time_[i] = now_;
      distance_[i] = best_distance + 1;
      return;
    }
    // No valid parent: i becomes free; its tree neighbours that could reach it again are
    // activated, and its children are orphaned in turn.
    for (uint32_t a = first_[i]; a < first_[i + 1]; ++a) {
      const uint32_t j = head_[a];
      if (sink_[j] != sink || parent_[j] == kFree) continue;
      if (TreeArcOpen(sister_[a], sink)) SetActive(j);
      const uint32_t p = parent_[j];
      if (p != kTerminal && p != kOrphan && head_[p] == i) MakeOrphan(j);
    }
    parent_[i] = kFree;
  }

  std::vector<uint32_t> first_, head_, sister_;
  std::vector<double> capacity_;  // residual capacity per arc
  std::vector<double> terminal_;  // residual source (> 0) or sink (< 0) capacity per node
  std::vector<uint32_t> parent_, time_, distance_;
  std::vector<uint8_t> sink_, active_;
  std::vector<uint32_t> queue_, queue_next_, orphans_;
  size_t queue_position_ = 0;
  uint32_t now_ = 0;
};

}  // namespace

MinCut::MinCut(size_t num_nodes, size_t expected_edges) : terminal_(num_nodes, 0.0) {
  if (num_nodes >= kOrphan) Fail("min cut: {} nodes, too many", num_nodes);
  edges_.reserve(expected_edges);
}

void MinCut::SetTerminalWeights(size_t node, double source_capacity, double sink_capacity) {
  if (!(source_capacity >= 0 && sink_capacity >= 0)) Fail("min cut: negative terminal weight");
  if (node >= terminal_.size()) Fail("min cut: no node {}", node);
  // Both links of a node carry min(source, sink) straight through it; only the rest is left.
  double& t = terminal_[node];
  const double to_source = std::max(t, 0.0) + source_capacity;
  const double to_sink = std::max(-t, 0.0) + sink_capacity;
  terminal_flow_ += std::min(to_source, to_sink);
  t = to_source - to_sink;
}

void MinCut::AddEdge(size_t a, size_t b, double capacity_ab, double capacity_ba) {
  if (!(capacity_ab >= 0 && capacity_ba >= 0)) Fail("min cut: negative capacity");
  if (a == b || a >= terminal_.size() || b >= terminal_.size())
    Fail("min cut: bad edge {} -> {}", a, b);
  edges_.push_back({static_cast<uint32_t>(a), static_cast<uint32_t>(b), capacity_ab, capacity_ba});
}

std::vector<bool> MinCut::Solve(double* flow) {
  const size_t n = terminal_.size();  // moved into the solver below
  const size_t num_arcs = 2 * edges_.size();
  if (num_arcs >= kOrphan) Fail("min cut: {} edges, too many", edges_.size());
  std::vector<uint32_t> first(n + 1, 0);
  for (const Edge& e : edges_) ++first[e.a + 1], ++first[e.b + 1];
  for (size_t i = 0; i < n; ++i) first[i + 1] += first[i];
  std::vector<uint32_t> head(num_arcs), sister(num_arcs);
  std::vector<double> capacity(num_arcs);
  {
    std::vector<uint32_t> next(first.begin(), first.end() - 1);
    for (const Edge& e : edges_) {
      const uint32_t ab = next[e.a]++, ba = next[e.b]++;
      head[ab] = e.b, head[ba] = e.a;
      sister[ab] = ba, sister[ba] = ab;
      capacity[ab] = e.capacity_ab, capacity[ba] = e.capacity_ba;
    }
  }
  std::vector<Edge>().swap(edges_);
  BoykovKolmogorov solver(std::move(first), std::move(head), std::move(sister), std::move(capacity),
                          std::move(terminal_));
  const double value = solver.Run();
  if (flow) *flow = terminal_flow_ + value;
  std::vector<bool> source_side(n);
  for (uint32_t i = 0; i < n; ++i) source_side[i] = solver.InSourceTree(i);
  return source_side;
}

}  // namespace varsfm
