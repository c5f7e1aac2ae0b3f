// The vocabulary tree on descriptors with exact truth (well separated clusters), its
// determinism at any thread count, and its file: round trip, and corrupt files refused.
#include "varsfm/matching/vocabulary_tree.h"

#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "varsfm/matching/vocabulary_tree_io.h"
#include "varsfm/util/error.h"
#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

constexpr int kDim = VocabularyTree::kDimension;

// `clusters` groups of `per_cluster` descriptors: group c is 200 in dimension c and small noise
// elsewhere, so groups are far apart and each descriptor nearest its own group's mean.
FeatureDescriptors ClusteredDescriptors(int clusters, int per_cluster, uint64_t seed) {
  Rng rng(seed);
  FeatureDescriptors descriptors(clusters * per_cluster, kDim);
  for (int c = 0; c < clusters; ++c)
    for (int k = 0; k < per_cluster; ++k) {
      const int row = c * per_cluster + k;
      for (int d = 0; d < kDim; ++d) descriptors(row, d) = static_cast<uint8_t>(rng() % 8);
      descriptors(row, c) = 200;
    }
  return descriptors;
}

TrainingDescriptors AsTraining(const FeatureDescriptors& descriptors) {
  return descriptors.cast<float>();
}

std::filesystem::path TempFile(const std::string& name) {
  // ctest runs each test in its own process, possibly at once: a name per process.
  return std::filesystem::temp_directory_path() /
         ("varsfm_" + name + "_" + std::to_string(::getpid()) + ".voc");
}

VocabularyTree SmallTree() {
  VocabularyTreeOptions options;
  options.branching = 4;
  options.depth = 3;
  return VocabularyTree::Train(AsTraining(ClusteredDescriptors(16, 40, 3)), options);
}

std::string ReadBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void WriteBytes(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

TEST(VocabularyTree, OneLevelSeparatesTheClusters) {
  const FeatureDescriptors descriptors = ClusteredDescriptors(10, 30, 1);
  VocabularyTreeOptions options;
  options.depth = 1;
  const VocabularyTree tree = VocabularyTree::Train(AsTraining(descriptors), options);
  ASSERT_EQ(tree.NumWords(), 10);
  const std::vector<int> words = tree.Quantize(descriptors);
  std::set<int> cluster_words;
  for (int c = 0; c < 10; ++c) {
    for (int k = 1; k < 30; ++k) EXPECT_EQ(words[c * 30 + k], words[c * 30]) << c;
    cluster_words.insert(words[c * 30]);
  }
  EXPECT_EQ(cluster_words.size(), 10u);
}

TEST(VocabularyTree, SmallNodesStayLeaves) {
  // 4 groups of 7, branching 4: the root splits into the groups, which (fewer than 2 x 4
  // descriptors each) do not split.
  VocabularyTreeOptions options;
  options.branching = 4;
  options.depth = 3;
  const VocabularyTree tree =
      VocabularyTree::Train(AsTraining(ClusteredDescriptors(4, 7, 2)), options);
  EXPECT_EQ(tree.NumWords(), 4);
  EXPECT_EQ(tree.nodes().size(), 5u);
}

TEST(VocabularyTree, SameTreeAtAnyThreadCount) {
  const TrainingDescriptors data = AsTraining(ClusteredDescriptors(30, 50, 4));
  VocabularyTreeOptions options;
  options.branching = 5;
  options.depth = 3;
  VocabularyTree one, many;
  {
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 1);
    one = VocabularyTree::Train(data, options);
  }
  {
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 4);
    many = VocabularyTree::Train(data, options);
  }
  ASSERT_EQ(one.nodes().size(), many.nodes().size());
  EXPECT_TRUE(one.centres() == many.centres());
  options.seed = 7;
  const VocabularyTree other = VocabularyTree::Train(data, options);
  EXPECT_GT(other.NumWords(), 1);
}

TEST(VocabularyTree, FileRoundTrip) {
  const VocabularyTree tree = SmallTree();
  const auto path = TempFile("round_trip");
  WriteVocabularyTree(tree, path);
  const VocabularyTree read = ReadVocabularyTree(path);
  EXPECT_EQ(read.branching(), tree.branching());
  ASSERT_EQ(read.nodes().size(), tree.nodes().size());
  for (size_t i = 0; i < tree.nodes().size(); ++i) {
    EXPECT_EQ(read.nodes()[i].first_child, tree.nodes()[i].first_child);
    EXPECT_EQ(read.nodes()[i].num_children, tree.nodes()[i].num_children);
  }
  EXPECT_TRUE(read.centres() == tree.centres());
  const FeatureDescriptors probe = ClusteredDescriptors(16, 5, 9);
  EXPECT_EQ(read.Quantize(probe), tree.Quantize(probe));
  std::filesystem::remove(path);
}

void ExpectRefused(const std::string& bytes, const std::string& expected) {
  const auto path = TempFile("corrupt");
  WriteBytes(path, bytes);
  try {
    ReadVocabularyTree(path);
    ADD_FAILURE() << "accepted; expected: " << expected;
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(expected), std::string::npos) << message;
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  std::filesystem::remove(path);
}

// Rewrites the trailing hash so that only the tree's own checks can refuse the bytes.
std::string Rehashed(std::string bytes) {
  uint64_t hash = 0xcbf29ce484222325ull;
  for (size_t i = 0; i + 8 < bytes.size(); ++i) {
    hash ^= static_cast<unsigned char>(bytes[i]);
    hash *= 0x100000001b3ull;
  }
  std::memcpy(bytes.data() + bytes.size() - 8, &hash, 8);
  return bytes;
}

TEST(VocabularyTree, CorruptFilesAreRefusedWithOneLine) {
  const auto path = TempFile("good");
  WriteVocabularyTree(SmallTree(), path);
  const std::string good = ReadBytes(path);
  std::filesystem::remove(path);

  ExpectRefused("", "is not a varsfm vocabulary tree");
  ExpectRefused("PLY\n" + good.substr(4), "is not a varsfm vocabulary tree");
  ExpectRefused(good.substr(0, good.size() - 100), "truncated");
  ExpectRefused(good + "x", "truncated");
  std::string flipped = good;
  flipped[good.size() / 2] ^= 0x10;
  ExpectRefused(flipped, "corrupt");
  std::string version = good;
  version[8] = 9;
  ExpectRefused(version, "format version 9");
  std::string dimension = good;
  dimension[12] = 64;
  ExpectRefused(dimension, "descriptors of 64 values");
  // A node count that would need terabytes: refused by the length, nothing allocated.
  std::string huge = good;
  huge[20] = huge[21] = huge[22] = huge[23] = static_cast<char>(0xff);
  ExpectRefused(huge, "truncated");
  // Well hashed but not a tree: the root's children start elsewhere; a node with too many.
  std::string bad_child = good;
  bad_child[24] = 2;
  ExpectRefused(Rehashed(bad_child), "children start at 2");
  std::string too_many = good;
  too_many[28] = 9;
  ExpectRefused(Rehashed(too_many), "more than the branching 4");
  std::string branching = good;
  branching[16] = 1;
  ExpectRefused(Rehashed(branching), "branching 1 is outside");
  EXPECT_EQ(Rehashed(good), good);  // the hash is the one the writer wrote
}

TEST(VocabularyTree, OptionsAreChecked) {
  VocabularyTreeOptions options;
  EXPECT_NO_THROW(options.Check());
  options.branching = 1;
  EXPECT_THROW(options.Check(), OptionError);
  options = {};
  options.depth = 0;
  EXPECT_THROW(options.Check(), OptionError);
  options = {};
  options.kmeans_iterations = 0;
  EXPECT_THROW(options.Check(), OptionError);
  EXPECT_THROW(VocabularyTree::Train(AsTraining(ClusteredDescriptors(1, 5, 1)), {}), Error);
}

}  // namespace
}  // namespace varsfm
