// Private helper of the manylight module: a counter-based RNG (directions and BSDF sampling
// come from the render module).
#pragma once

#include <cstdint>

#include "rayscout/core/random.h"

namespace rayscout::manylight_detail {

/// One SplitMix64 step as a hash: the stream's next output from state z.
inline uint64_t hash64(uint64_t z) { return mix64(z + kGolden64); }

/// The preprocess keys its streams (seed, small tag, index) with tags below 2^32; the render
/// passes key theirs (seed + pass, kRenderStream | point, sample), so that no shading point's
/// stream in pass 0 repeats a preprocess stream (point 0x11A7 would otherwise draw the numbers
/// of the light path with its sample's index).
inline constexpr uint64_t kRenderStream = uint64_t(1) << 32;

/// PCG32 seeded from a key tuple, so results never depend on thread scheduling.
class Rng {
 public:
  Rng(uint64_t a, uint64_t b = 0, uint64_t c = 0) {
    state_ = hash64(a ^ hash64(b ^ hash64(c)));
    inc_ = (hash64(state_ + 0x632BE59BD9B4E019ull) << 1u) | 1u;
    next();
  }
  uint32_t next() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ull + inc_;
    const uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    const uint32_t rot = uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32 - rot) & 31));
  }
  /// 64 uniform random bits (two outputs).
  uint64_t bits64() { const uint64_t high = next(); return (high << 32) | next(); }
  /// Uniform in [0, 1).
  float uniform() { return float(next() >> 8) * (1.0f / 16777216.0f); }
  /// Uniform integer in [0, n), exactly: multiply-shift with Lemire's rejection of the
  /// 2^32 mod n low products that would favour some values (the callers weigh by exactly 1/n).
  uint32_t below(uint32_t n) {
    uint64_t m = uint64_t(next()) * n;
    if (uint32_t(m) < n) {
      const uint32_t threshold = (0u - n) % n;
      while (uint32_t(m) < threshold) m = uint64_t(next()) * n;
    }
    return uint32_t(m >> 32);
  }

 private:
  uint64_t state_, inc_;
};

}  // namespace rayscout::manylight_detail
