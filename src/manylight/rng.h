// Private helper of the manylight module: a counter-based RNG (directions and BSDF sampling
// come from the render module).
#pragma once

#include <cstdint>

namespace rayscout::manylight_detail {

/// SplitMix64 finaliser: a good 64-bit mix.
inline uint64_t mix64(uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// PCG32 seeded from a key tuple, so results never depend on thread scheduling.
class Rng {
 public:
  Rng(uint64_t a, uint64_t b = 0, uint64_t c = 0) {
    state_ = mix64(a ^ mix64(b ^ mix64(c)));
    inc_ = (mix64(state_ + 0x632BE59BD9B4E019ull) << 1u) | 1u;
    next();
  }
  uint32_t next() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ull + inc_;
    const uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    const uint32_t rot = uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32 - rot) & 31));
  }
  /// Uniform in [0, 1).
  float uniform() { return float(next() >> 8) * (1.0f / 16777216.0f); }
  double uniform_double() { return double(next()) * (1.0 / 4294967296.0); }
  /// Uniform integer in [0, n).
  uint32_t below(uint32_t n) { return uint32_t((uint64_t(next()) * n) >> 32); }

 private:
  uint64_t state_, inc_;
};

}  // namespace rayscout::manylight_detail
