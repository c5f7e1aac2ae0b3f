#include "varsfm/matching/vocabulary_tree.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <optional>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "varsfm/util/error.h"
#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

constexpr int kDim = VocabularyTree::kDimension;

float SquaredDistance(const float* a, const float* b) {
  float sum = 0;
  for (int i = 0; i < kDim; ++i) {
    const float d = a[i] - b[i];
    sum += d * d;
  }
  return sum;
}

// Index of the nearest of `count` centre rows starting at `first` (ties: the lowest).
int Nearest(const TrainingDescriptors& centres, int first, int count, const float* x) {
  int best = 0;
  float best_distance = std::numeric_limits<float>::infinity();
  for (int c = 0; c < count; ++c) {
    const float distance = SquaredDistance(centres.row(first + c).data(), x);
    if (distance < best_distance) {
      best_distance = distance;
      best = c;
    }
  }
  return best;
}

double Uniform(Rng& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

struct Clusters {
  TrainingDescriptors centres;                 // non-empty clusters only
  std::vector<std::vector<uint32_t>> members;  // rows of the data in each
};

// k-means++ seeding (Arthur & Vassilvitskii 2007): each next centre drawn with probability
// proportional to the squared distance to the nearest one chosen.
TrainingDescriptors SeedCentres(const TrainingDescriptors& data, const std::vector<uint32_t>& rows,
                                int k, Rng& rng) {
  TrainingDescriptors centres(k, kDim);
  std::vector<double> nearest(rows.size(), std::numeric_limits<double>::infinity());
  size_t chosen = static_cast<size_t>(Uniform(rng) * rows.size());
  for (int c = 0; c < k; ++c) {
    centres.row(c) = data.row(rows[std::min(chosen, rows.size() - 1)]);
    double total = 0;
    for (size_t i = 0; i < rows.size(); ++i) {
      nearest[i] = std::min<double>(
          nearest[i], SquaredDistance(centres.row(c).data(), data.row(rows[i]).data()));
      total += nearest[i];
    }
    if (total <= 0) {  // every point sits on a centre: the rest are arbitrary but distinct rows
      chosen = (chosen + 1) % rows.size();
      continue;
    }
    const double target = Uniform(rng) * total;
    double cumulative = 0;
    chosen = rows.size() - 1;
    for (size_t i = 0; i < rows.size(); ++i) {
      cumulative += nearest[i];
      if (cumulative > target) {
        chosen = i;
        break;
      }
    }
  }
  return centres;
}

// Lloyd's k-means over data rows `rows`. Assignment is parallel (each point on its own), the
// centre sums serial in row order: the same bits at any thread count.
Clusters KMeans(const TrainingDescriptors& data, const std::vector<uint32_t>& rows, int k,
                int iterations, uint64_t seed) {
  Rng rng(seed);
  TrainingDescriptors centres = SeedCentres(data, rows, k, rng);
  std::vector<int> label(rows.size(), -1);
  for (int iteration = 0; iteration < iterations; ++iteration) {
    std::atomic<bool> changed = false;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, rows.size(), 1024),
                      [&](const tbb::blocked_range<size_t>& range) {
                        bool local_changed = false;
                        for (size_t i = range.begin(); i < range.end(); ++i) {
                          const int c = Nearest(centres, 0, k, data.row(rows[i]).data());
                          local_changed |= c != label[i];
                          label[i] = c;
                        }
                        if (local_changed) changed = true;
                      });
    if (!changed) break;
    Eigen::MatrixXd sums = Eigen::MatrixXd::Zero(k, kDim);
    std::vector<size_t> counts(k, 0);
    for (size_t i = 0; i < rows.size(); ++i) {
      sums.row(label[i]) += data.row(rows[i]).cast<double>();
      ++counts[label[i]];
    }
    // An empty cluster keeps its centre; it is dropped below if it stays empty.
    for (int c = 0; c < k; ++c)
      if (counts[c] > 0) centres.row(c) = (sums.row(c) / counts[c]).cast<float>();
  }
  Clusters clusters;
  std::vector<std::vector<uint32_t>> members(k);
  for (size_t i = 0; i < rows.size(); ++i) members[label[i]].push_back(rows[i]);
  std::vector<int> kept;
  for (int c = 0; c < k; ++c)
    if (!members[c].empty()) kept.push_back(c);
  clusters.centres.resize(static_cast<Eigen::Index>(kept.size()), kDim);
  for (size_t c = 0; c < kept.size(); ++c) {
    clusters.centres.row(static_cast<Eigen::Index>(c)) = centres.row(kept[c]);
    clusters.members.push_back(std::move(members[kept[c]]));
  }
  return clusters;
}

}  // namespace

void VocabularyTreeOptions::Check() const {
  CheckInRange("--vocabulary-branching", branching, 2, 256);
  CheckInRange("--vocabulary-depth", depth, 1, 8);
  CheckAtLeast("kmeans_iterations", kmeans_iterations, 1);
}

VocabularyTree::VocabularyTree(int branching, std::vector<Node> nodes, TrainingDescriptors centres)
    : branching_(branching), nodes_(std::move(nodes)), centres_(std::move(centres)) {
  if (branching_ < 2 || branching_ > 256)
    Fail("vocabulary tree: branching {} is outside [2, 256]", branching_);
  if (nodes_.empty() || nodes_[0].num_children == 0)
    Fail("vocabulary tree: the root has no children");
  if (centres_.rows() != static_cast<Eigen::Index>(nodes_.size()) || centres_.cols() != kDim)
    Fail("vocabulary tree: {} centres of {} values for {} nodes", centres_.rows(), centres_.cols(),
         nodes_.size());
  // Breadth first: the children of each inner node follow those of the inner nodes before it,
  // so every node but the root has exactly one parent and a larger index than it.
  size_t next_child = 1;
  for (size_t i = 0; i < nodes_.size(); ++i) {
    if (i > 0 && i >= next_child) Fail("vocabulary tree: node {} has no parent", i);
    const Node& node = nodes_[i];
    if (node.num_children > static_cast<uint32_t>(branching_))
      Fail("vocabulary tree: node {} has {} children, more than the branching {}", i,
           node.num_children, branching_);
    if (node.num_children == 0) continue;
    if (node.first_child != next_child)
      Fail("vocabulary tree: node {}'s children start at {}, expected {}", i, node.first_child,
           next_child);
    next_child += node.num_children;
    if (next_child > nodes_.size())
      Fail("vocabulary tree: node {}'s children go past the {} nodes", i, nodes_.size());
  }
  if (!centres_.allFinite()) Fail("vocabulary tree: a centre is not finite");
  NumberLeaves();
}

void VocabularyTree::NumberLeaves() {
  word_of_node_.assign(nodes_.size(), -1);
  num_words_ = 0;
  for (size_t i = 0; i < nodes_.size(); ++i)
    if (nodes_[i].num_children == 0) word_of_node_[i] = num_words_++;
}

VocabularyTree VocabularyTree::Train(const TrainingDescriptors& descriptors,
                                     const VocabularyTreeOptions& options, OptionsCheck check) {
  if (check == OptionsCheck::kByStage) options.Check();
  if (descriptors.cols() != kDim)
    Fail("vocabulary tree: descriptors have {} values, expected {}", descriptors.cols(), kDim);
  const size_t min_members = 2 * static_cast<size_t>(options.branching);
  if (static_cast<size_t>(descriptors.rows()) < min_members)
    Fail("vocabulary tree: {} descriptors are too few to train on (at least {})",
         descriptors.rows(), min_members);
  std::vector<Node> nodes(1);
  std::vector<Eigen::RowVectorXf> centre_rows(1, Eigen::RowVectorXf::Zero(kDim));
  std::vector<uint32_t> level_nodes = {0};
  std::vector<std::vector<uint32_t>> level_members(1);
  for (uint32_t i = 0; i < descriptors.rows(); ++i) level_members[0].push_back(i);
  for (int level = 0; level < options.depth && !level_nodes.empty(); ++level) {
    // Nodes of a level are clustered in parallel, each seeded by its index.
    std::vector<std::optional<Clusters>> clusters(level_nodes.size());
    tbb::parallel_for(size_t{0}, level_nodes.size(), [&](size_t n) {
      if (level_members[n].size() < min_members) return;
      clusters[n] = KMeans(descriptors, level_members[n], options.branching,
                           options.kmeans_iterations, DeriveSeed(options.seed, level_nodes[n]));
    });
    std::vector<uint32_t> next_nodes;
    std::vector<std::vector<uint32_t>> next_members;
    for (size_t n = 0; n < level_nodes.size(); ++n) {
      if (!clusters[n] || clusters[n]->members.size() < 2) continue;  // stays a leaf
      Node& node = nodes[level_nodes[n]];
      node.first_child = static_cast<uint32_t>(nodes.size());
      node.num_children = static_cast<uint32_t>(clusters[n]->members.size());
      for (size_t c = 0; c < clusters[n]->members.size(); ++c) {
        next_nodes.push_back(static_cast<uint32_t>(nodes.size()));
        nodes.emplace_back();
        centre_rows.push_back(clusters[n]->centres.row(static_cast<Eigen::Index>(c)));
        next_members.push_back(std::move(clusters[n]->members[c]));
      }
    }
    level_nodes = std::move(next_nodes);
    level_members = std::move(next_members);
  }
  TrainingDescriptors centres(static_cast<Eigen::Index>(nodes.size()), kDim);
  for (size_t i = 0; i < nodes.size(); ++i)
    centres.row(static_cast<Eigen::Index>(i)) = centre_rows[i];
  return VocabularyTree(options.branching, std::move(nodes), std::move(centres));
}

int VocabularyTree::Quantize(const float* descriptor) const {
  size_t node = 0;
  while (nodes_[node].num_children > 0) {
    const Node& n = nodes_[node];
    node =
        n.first_child + static_cast<size_t>(Nearest(centres_, static_cast<int>(n.first_child),
                                                    static_cast<int>(n.num_children), descriptor));
  }
  return word_of_node_[node];
}

std::vector<int> VocabularyTree::Quantize(const FeatureDescriptors& descriptors) const {
  if (descriptors.rows() > 0 && descriptors.cols() != kDim)
    Fail("vocabulary tree: descriptors have {} values, expected {}", descriptors.cols(), kDim);
  std::vector<int> words(static_cast<size_t>(descriptors.rows()));
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, descriptors.rows(), 256),
                    [&](const tbb::blocked_range<Eigen::Index>& range) {
                      Eigen::RowVectorXf row(kDim);
                      for (Eigen::Index i = range.begin(); i < range.end(); ++i) {
                        row = descriptors.row(i).cast<float>();
                        words[static_cast<size_t>(i)] = Quantize(row.data());
                      }
                    });
  return words;
}

}  // namespace varsfm
