// The vocabulary tree reader (matching/vocabulary_tree_io.cc): a file given with
// `match --vocabulary`. Only varsfm::Error may leave it. Each input is read as it is and again
// with its trailing hash recomputed, so that mutations reach the checks of the tree's structure
// behind the hash.
#include <cstring>

#include "fuzz_support.h"
#include "varsfm/matching/vocabulary_tree_io.h"
#include "varsfm/util/error.h"

namespace {

void Read(const std::filesystem::path& file, const uint8_t* data, size_t size) {
  varsfm::fuzz::WriteBytes(file, data, size);
  try {
    varsfm::ReadVocabularyTree(file);
  } catch (const varsfm::Error&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto file = varsfm::fuzz::ScratchDir() / "tree.voc";
  Read(file, data, size);
  if (size < 8) return 0;
  std::vector<uint8_t> rehashed(data, data + size);
  uint64_t hash = 0xcbf29ce484222325ull;  // FNV-1a, as the writer
  for (size_t i = 0; i + 8 < size; ++i) {
    hash ^= rehashed[i];
    hash *= 0x100000001b3ull;
  }
  std::memcpy(rehashed.data() + size - 8, &hash, 8);
  Read(file, rehashed.data(), size);
  return 0;
}
