// Private helpers of the manylight module: a counter-based RNG and direction sampling.
#pragma once

#include <cmath>
#include <cstdint>

#include "rayscout/manylight/brdf.h"

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

/// Orthonormal basis around unit n (Duff et al. 2017).
inline void basis(const Vec3& n, Vec3& t, Vec3& b) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float bb = n.x * n.y * a;
  t = Vec3(1.0f + sign * n.x * n.x * a, sign * bb, -sign * n.x);
  b = Vec3(bb, sign + n.y * n.y * a, -n.y);
}

inline Vec3 local_to_world(const Vec3& n, float x, float y, float z) {
  Vec3 t, b;
  basis(n, t, b);
  return t * x + b * y + n * z;
}

/// Cosine-weighted direction around n; pdf = cos / pi.
inline Vec3 sample_cosine(const Vec3& n, float u1, float u2) {
  const float r = std::sqrt(u1), phi = 2.0f * kPi * u2;
  return local_to_world(n, r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1.0f - u1)));
}

/// Direction around axis with density (e + 1) / (2 pi) cos^e.
inline Vec3 sample_phong(const Vec3& axis, float e, float u1, float u2) {
  const float c = std::pow(u1, 1.0f / (e + 1.0f));
  const float s = std::sqrt(std::max(0.0f, 1.0f - c * c)), phi = 2.0f * kPi * u2;
  return local_to_world(axis, s * std::cos(phi), s * std::sin(phi), c);
}

/// Offsets a surface point along its normal by `offset` (scene-scaled).
inline Vec3 offset_point(const Vec3& p, const Vec3& n, float offset) { return p + n * offset; }

}  // namespace rayscout::manylight_detail
