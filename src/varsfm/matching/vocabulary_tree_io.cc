#include "varsfm/matching/vocabulary_tree_io.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "varsfm/util/atomic_file.h"
#include "varsfm/util/error.h"
#include "varsfm/util/fnv1a.h"
#include "varsfm/util/little_endian.h"

namespace varsfm {
namespace {

// The centres are read and written as one block of host floats: the file is little-endian.
static_assert(std::endian::native == std::endian::little, "the file is little-endian");

constexpr char kMagic[8] = {'V', 'S', 'F', 'M', 'V', 'O', 'C', '\0'};
constexpr size_t kHeaderBytes = sizeof(kMagic) + 4 * sizeof(uint32_t);
constexpr size_t kNodeBytes = 2 * sizeof(uint32_t);
constexpr size_t kCentreBytes = VocabularyTree::kDimension * sizeof(float);

// The value at `offset`, which moves past it.
template <typename T>
T Get(const std::string& bytes, size_t& offset) {
  const T value = GetLittleEndian<T>(bytes.data() + offset);
  offset += sizeof(T);
  return value;
}

}  // namespace

void WriteVocabularyTree(const VocabularyTree& tree, const std::filesystem::path& path) {
  std::string bytes(kMagic, sizeof(kMagic));
  AppendLittleEndian<uint32_t>(&bytes, kVocabularyFileVersion);
  AppendLittleEndian<uint32_t>(&bytes, VocabularyTree::kDimension);
  AppendLittleEndian<uint32_t>(&bytes, static_cast<uint32_t>(tree.branching()));
  AppendLittleEndian<uint32_t>(&bytes, static_cast<uint32_t>(tree.nodes().size()));
  for (const VocabularyTree::Node& node : tree.nodes()) {
    AppendLittleEndian<uint32_t>(&bytes, node.first_child);
    AppendLittleEndian<uint32_t>(&bytes, node.num_children);
  }
  const auto& centres = tree.centres();
  bytes.append(reinterpret_cast<const char*>(centres.data()),
               static_cast<size_t>(centres.size()) * sizeof(float));
  AppendLittleEndian<uint64_t>(&bytes, Fnv1a(bytes.data(), bytes.size()));
  WriteFileAtomically(path, [&](std::ostream& out) {
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  });
}

VocabularyTree ReadVocabularyTree(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) Fail("cannot read the vocabulary tree {}", path.string());
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string name = path.string();
  if (bytes.size() < kHeaderBytes + sizeof(uint64_t) ||
      std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0)
    Fail("{} is not a varsfm vocabulary tree", name);
  size_t offset = sizeof(kMagic);
  const uint32_t version = Get<uint32_t>(bytes, offset);
  if (version != kVocabularyFileVersion)
    Fail("{}: vocabulary tree format version {}, this varsfm reads version {}", name, version,
         kVocabularyFileVersion);
  const uint32_t dimension = Get<uint32_t>(bytes, offset);
  if (dimension != VocabularyTree::kDimension)
    Fail("{}: descriptors of {} values, expected {}", name, dimension, VocabularyTree::kDimension);
  const uint32_t branching = Get<uint32_t>(bytes, offset);
  const uint32_t num_nodes = Get<uint32_t>(bytes, offset);
  // The length must match the count exactly before anything is sized from it.
  const size_t body = bytes.size() - kHeaderBytes - sizeof(uint64_t);
  if (body % (kNodeBytes + kCentreBytes) != 0 || body / (kNodeBytes + kCentreBytes) != num_nodes)
    Fail("{}: {} bytes do not hold the {} nodes the header gives (truncated?)", name, bytes.size(),
         num_nodes);
  size_t hash_offset = bytes.size() - sizeof(uint64_t);
  if (Get<uint64_t>(bytes, hash_offset) != Fnv1a(bytes.data(), bytes.size() - sizeof(uint64_t)))
    Fail("{}: the vocabulary tree is corrupt (its hash does not match)", name);
  std::vector<VocabularyTree::Node> nodes(num_nodes);
  for (VocabularyTree::Node& node : nodes) {
    node.first_child = Get<uint32_t>(bytes, offset);
    node.num_children = Get<uint32_t>(bytes, offset);
  }
  TrainingDescriptors centres(static_cast<Eigen::Index>(num_nodes), VocabularyTree::kDimension);
  std::memcpy(centres.data(), bytes.data() + offset, num_nodes * kCentreBytes);
  try {
    return VocabularyTree(static_cast<int>(std::min<uint32_t>(branching, 1u << 30)),
                          std::move(nodes), std::move(centres));
  } catch (const Error& e) {
    Fail("{}: {}", name, e.what());
  }
}

}  // namespace varsfm
