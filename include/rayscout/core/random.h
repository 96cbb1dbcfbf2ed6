// SplitMix64 (Steele, Lea, Flood, "Fast splittable pseudorandom number generators", 2014): the
// 64-bit mix and stream behind the renderer's sampler and the shafts' sample rays; manylight's
// PCG32 is seeded through it. (DACRT picks its sample rays with a plain xorshift64.)
#pragma once

#include <cstdint>

namespace rayscout {

/// SplitMix64's increment (the golden ratio in 64 bits).
inline constexpr uint64_t kGolden64 = 0x9E3779B97F4A7C15ull;

/// The 64-bit finaliser of SplitMix64: a bijective mix with full avalanche.
constexpr uint64_t mix64(uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}

/// The SplitMix64 stream: output k of seed s is mix64(s + (k + 1) kGolden64).
struct SplitMix64 {
  uint64_t state = 0;
  uint64_t next() { return mix64(state += kGolden64); }
  /// Uniform float in [0, 1) from the top 24 bits.
  float uniform() { return float(next() >> 40) * (1.0f / 16777216.0f); }
};

}  // namespace rayscout
