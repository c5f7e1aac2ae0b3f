#pragma once
// FNV-1a, 64 bits (Fowler, Noll & Vo): a fast, non-cryptographic hash for checksums and file
// fingerprints written into files, so its constants are fixed by the algorithm, not by us.
#include <cstddef>
#include <cstdint>

namespace varsfm {

inline constexpr uint64_t kFnv1aOffsetBasis = 0xcbf29ce484222325ull;

// The hash of `size` bytes at `data`, continued from `hash` (the offset basis for a new hash).
inline uint64_t Fnv1a(const char* data, size_t size, uint64_t hash = kFnv1aOffsetBasis) {
  for (size_t i = 0; i < size; ++i) {
    hash ^= static_cast<unsigned char>(data[i]);
    hash *= 0x100000001b3ull;
  }
  return hash;
}

}  // namespace varsfm
