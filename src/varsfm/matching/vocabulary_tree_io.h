#pragma once
// The vocabulary tree's file (`match --vocabulary FILE`), little-endian:
//   8 bytes  "VSFMVOC\0"
//   uint32   format version (1)
//   uint32   descriptor dimension (128)
//   uint32   branching
//   uint32   number of nodes N
//   N x (uint32 first child, uint32 number of children)   breadth first, as VocabularyTree
//   N x 128 float32                                        the centres (the root's zero)
//   uint64   FNV-1a hash of every byte before it
// Nothing is sized from a count before the file's length confirms it.
#include <filesystem>

#include "varsfm/matching/vocabulary_tree.h"

namespace varsfm {

inline constexpr uint32_t kVocabularyFileVersion = 1;

// Writes atomically (a temporary renamed into place); throws varsfm::Error if it cannot.
void WriteVocabularyTree(const VocabularyTree& tree, const std::filesystem::path& path);

// Throws varsfm::Error with one line naming the file and the problem for a missing, truncated,
// corrupt (hash) or malformed file, or one of another version.
VocabularyTree ReadVocabularyTree(const std::filesystem::path& path);

}  // namespace varsfm
