#pragma once
// Deterministic randomness: every randomised algorithm takes a seed and owns its generator, so a
// fixed seed gives the same result whatever the thread count (no global state).
#include <cstdint>
#include <random>

namespace varsfm {

using Rng = std::mt19937_64;
inline constexpr uint64_t kDefaultSeed = 42;

// A per-item seed derived from a base seed, for parallel loops (SplitMix64 mixing).
inline uint64_t DeriveSeed(uint64_t base, uint64_t index) {
  uint64_t z = base + 0x9E3779B97F4A7C15ull * (index + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace varsfm
