// AVX2 helpers of the DACRT kernels (used when AVX-512 is not available): the 8-lane slab
// test of intersect_box and a left-pack ("compress") of 8 ray ids by a lane mask.
#pragma once

#if defined(__AVX2__) && !defined(__AVX512F__)

#include <immintrin.h>

#include <array>
#include <cstdint>

namespace rayscout::dacrt::avx2 {

/// For every 8-bit lane mask, the permutation that moves the selected lanes to the front
/// (in order), as _mm256_permutevar8x32_epi32 indices.
struct alignas(32) Permutation {
  int idx[8];
};

constexpr std::array<Permutation, 256> make_compress_table() {
  std::array<Permutation, 256> t{};
  for (int m = 0; m < 256; ++m) {
    int k = 0;
    for (int l = 0; l < 8; ++l) {
      t[m].idx[l] = 0;
      if ((m >> l) & 1) t[m].idx[k++] = l;
    }
  }
  return t;
}

inline constexpr std::array<Permutation, 256> kCompressTable = make_compress_table();

/// The lanes of ids selected by mask, packed to the front (the rest is unspecified).
inline __m256i compress(__m256i ids, int mask) {
  return _mm256_permutevar8x32_epi32(ids, _mm256_load_si256(reinterpret_cast<const __m256i*>(kCompressTable[mask].idx)));
}

/// One slab of intersect_box for 8 lanes, as the AVX-512 kernels: near and far planes chosen
/// by the sign of inv (blendv reads the sign bit), the far end scaled by robust; max/min keep
/// the running value on NaN.
inline void slab(__m256 lo, __m256 hi, __m256 o, __m256 inv, __m256 robust, __m256& tnear, __m256& tfar) {
  const __m256 t0 = _mm256_mul_ps(_mm256_sub_ps(lo, o), inv);
  const __m256 t1 = _mm256_mul_ps(_mm256_sub_ps(hi, o), inv);
  const __m256 a = _mm256_blendv_ps(t0, t1, inv);
  const __m256 b = _mm256_mul_ps(_mm256_blendv_ps(t1, t0, inv), robust);
  tnear = _mm256_max_ps(a, tnear);  // a > tnear ? a : tnear
  tfar = _mm256_min_ps(b, tfar);    // b < tfar ? b : tfar
}

}  // namespace rayscout::dacrt::avx2

#endif  // __AVX2__ && !__AVX512F__
