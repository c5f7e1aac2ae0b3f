#pragma once
// A vocabulary tree (Nistér & Stewénius, "Scalable Recognition with a Vocabulary Tree", CVPR
// 2006): hierarchical k-means over SIFT descriptors, `branching` clusters per node down to
// `depth` levels; a descriptor's visual word is the leaf reached by descending to the nearest
// child centre at each level. Trained on the set's own descriptors (nothing downloaded), so a
// tree fits the set it indexes; it can be saved and reused (vocabulary_tree_io.h).
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "varsfm/feature/types.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/random.h"

namespace varsfm {

// Descriptors as k-means sees them: one float row per descriptor, 128 columns for SIFT.
using TrainingDescriptors = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct VocabularyTreeOptions {
  int branching = 10;          // k of each node's k-means
  int depth = 4;               // levels below the root: at most branching^depth words
  int kmeans_iterations = 10;  // Lloyd iterations per node at most (fewer once stable)
  uint64_t seed = kDefaultSeed;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

class VocabularyTree {
 public:
  static constexpr int kDimension = 128;

  // A node: its children are nodes first_child .. first_child + num_children - 1 (nodes are
  // stored breadth first, so a child's index is above its parent's); a leaf has none and
  // carries a word.
  struct Node {
    uint32_t first_child = 0;
    uint32_t num_children = 0;
  };

  VocabularyTree() = default;
  // From stored parts; throws varsfm::Error unless they form a tree (breadth-first layout, every
  // node but the root the child of exactly one, centres finite). `centres` has one row per node
  // (the root's is unused).
  VocabularyTree(int branching, std::vector<Node> nodes, TrainingDescriptors centres);

  // Hierarchical k-means over `descriptors` (rows; k-means++ seeding, seeded per node so the
  // tree is the same at any thread count). A node with fewer than 2 x branching descriptors
  // becomes a leaf. `check`: kDoneByCaller when the caller checked `options` (the match stage).
  static VocabularyTree Train(const TrainingDescriptors& descriptors,
                              const VocabularyTreeOptions& options,
                              OptionsCheck check = OptionsCheck::kByStage);

  int branching() const { return branching_; }
  int NumWords() const { return num_words_; }
  const std::vector<Node>& nodes() const { return nodes_; }
  const TrainingDescriptors& centres() const { return centres_; }

  // The word (0 .. NumWords() - 1) of one descriptor of kDimension values.
  int Quantize(const float* descriptor) const;
  // The word of each row (multi-threaded).
  std::vector<int> Quantize(const FeatureDescriptors& descriptors) const;

 private:
  void NumberLeaves();

  int branching_ = 0;
  std::vector<Node> nodes_;
  TrainingDescriptors centres_;
  std::vector<int> word_of_node_;  // -1 for inner nodes
  int num_words_ = 0;
};

}  // namespace varsfm
