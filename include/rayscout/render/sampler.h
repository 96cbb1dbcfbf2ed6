// Counter-based random numbers: a pure hash of (seed, pixel, sample, bounce, dimension), no
// state, so results do not depend on thread count or on the order work is done in.
#pragma once

#include <cstdint>

namespace rayscout {

/// The 64-bit finaliser of SplitMix64 (Steele et al., "Fast splittable pseudorandom number
/// generators", 2014): a bijective mix with full avalanche.
constexpr uint64_t mix64(uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}

/// Random numbers of one path vertex: the key (seed, pixel, sample, bounce) is hashed once,
/// dimension d is then output d of a SplitMix64 stream seeded with it. Dimensions in use:
/// 0-3 camera (pixel jitter, lens) at bounce 0; 4-6 BSDF sampling; 8 and up light and AO
/// samples (see kDimLights).
class PathSampler {
 public:
  PathSampler(uint64_t seed, uint32_t pixel, uint32_t sample, uint32_t bounce)
      : seed_(seed), pixel_(pixel) {
    uint64_t h = mix64(seed + 0x9E3779B97F4A7C15ULL);
    h = mix64(h ^ ((uint64_t(pixel) << 32) | sample));
    key_ = mix64(h ^ bounce);
  }
  /// Uniform float in [0, 1), 24 random bits.
  float get(uint32_t dim) const { return float(bits(dim) >> 40) * 0x1p-24f; }
  /// 64 random bits of dimension dim.
  uint64_t bits(uint32_t dim) const { return mix64(key_ + (uint64_t(dim) + 1) * 0x9E3779B97F4A7C15ULL); }
  /// A sampler of the same seed and pixel that no (sample, bounce) key reaches: per-pixel choices.
  PathSampler pixel_sampler() const { return {seed_, pixel_, 0xFFFFFFFFu, 0xFFFFFFFFu}; }

 private:
  uint64_t seed_;
  uint32_t pixel_;
  uint64_t key_;
};

inline constexpr uint32_t kDimPixel = 0;   ///< 2 dims: position inside the pixel
inline constexpr uint32_t kDimLens = 2;    ///< 2 dims: thin-lens position
inline constexpr uint32_t kDimBsdf = 4;    ///< 3 dims: lobe choice, direction
inline constexpr uint32_t kDimLights = 8;  ///< 3 dims per light/AO sample k: 8 + 3k ...

}  // namespace rayscout
