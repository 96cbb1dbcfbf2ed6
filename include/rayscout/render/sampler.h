// Counter-based random numbers: a pure hash of (seed, pixel, sample, bounce, dimension), no
// state, so results do not depend on thread count or on the order work is done in.
#pragma once

#include <cstdint>

#include "rayscout/core/random.h"

namespace rayscout {

/// Random numbers of one path vertex: the key (seed, pixel, sample, bounce) is hashed once,
/// dimension d is then output d of a SplitMix64 stream seeded with it. The dimensions in use
/// are the kDim constants below.
class PathSampler {
 public:
  PathSampler(uint64_t seed, uint32_t pixel, uint32_t sample, uint32_t bounce)
      : seed_(seed), pixel_(pixel) {
    uint64_t h = mix64(seed + kGolden64);
    h = mix64(h ^ ((uint64_t(pixel) << 32) | sample));
    key_ = mix64(h ^ bounce);
  }
  /// Uniform float in [0, 1), 24 random bits.
  float get(uint32_t dim) const { return float(bits(dim) >> 40) * 0x1p-24f; }
  /// 64 random bits of dimension dim.
  uint64_t bits(uint32_t dim) const { return mix64(key_ + (uint64_t(dim) + 1) * kGolden64); }
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
inline constexpr uint32_t kDimRoulette = 7;  ///< 1 dim: Russian roulette of the path
inline constexpr uint32_t kDimLights = 8;  ///< 3 dims per light/AO sample k, see light_sample_dim

/// First of the 3 dimensions of light or AO sample k of a vertex (choice bits, then a point
/// or a direction), so that no two samples share one.
inline constexpr uint32_t light_sample_dim(int k) { return kDimLights + 3 * uint32_t(k); }

}  // namespace rayscout
