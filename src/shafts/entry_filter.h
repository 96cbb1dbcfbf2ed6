// Entry filter (private): box-tests a candidate list's quantised entry boxes against a ray,
// eight at a time with AVX2, and returns the hit entries sorted near first.
#pragma once

#include <cmath>
#include <cstdint>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include "entry_box_codec.h"
#include "rayscout/shafts/shaft_collection.h"

namespace rayscout::detail {

/// Relative widening of a slab's far distance, for either sign (Ize 2013's idea; the entry
/// boxes are quantised outward, so this only has to cover the slab test's own rounding).
inline constexpr float kEntryFarWiden = 4.0e-7f;

/// Writes the entries whose (widened) box the ray meets within [near, far] to refs/dist,
/// sorted by entry distance (Sorted) or in list order; returns their count. NaN slab
/// distances (0 * inf for a ray in a box plane) leave that axis unconstrained: conservative.
/// The AVX2 and the scalar path compute the same numbers but for NaN far limits, where both
/// are conservative (_mm256_min_ps and std::fmin treat NaN differently).
template <bool Sorted>
inline int filter_entries(const EntryBoxCodec& codec, const Candidates& c, const Vec3& org, const Vec3& inv_dir,
                          float near, float far, uint32_t* refs, float* dist) {
  const int len = int(c.list.size());
  int n = 0;
  auto insert = [&](int k, float d) {
    int j = n++;
    if constexpr (Sorted)
      while (j > 0 && dist[j - 1] > d) { dist[j] = dist[j - 1]; refs[j] = refs[j - 1]; --j; }
    dist[j] = d;
    refs[j] = c.list[size_t(k)];
  };
#if defined(__AVX2__)
  const uint8_t* rows = c.boxes;
  const __m256 ninf = _mm256_set1_ps(-INFINITY), pinf = _mm256_set1_ps(INFINITY);
  const __m256 rel = _mm256_set1_ps(kEntryFarWiden), signmask = _mm256_set1_ps(-0.0f);
  alignas(32) float tn[8];
  for (int chunk = 0; chunk < len; chunk += 8) {
    __m256 tnear = _mm256_set1_ps(near), tfar = _mm256_set1_ps(far);
    for (int a = 0; a < 3; ++a) {
      const __m256 base = _mm256_set1_ps(codec.base(a)), step = _mm256_set1_ps(codec.step(a));
      const __m256 m = _mm256_set1_ps(codec.margin()), o = _mm256_set1_ps(org[a]), inv = _mm256_set1_ps(inv_dir[a]);
      auto row = [&](int r) {  // 8 quantised bounds of row r as floats
        const __m128i bytes = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(rows + r * len + chunk));
        return _mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(bytes));
      };
      const __m256 lo = _mm256_sub_ps(_mm256_add_ps(base, _mm256_mul_ps(row(a), step)), m);
      const __m256 hi = _mm256_add_ps(_mm256_add_ps(base, _mm256_mul_ps(row(3 + a), step)), m);
      const __m256 ta = _mm256_mul_ps(_mm256_sub_ps(lo, o), inv), tb = _mm256_mul_ps(_mm256_sub_ps(hi, o), inv);
      const __m256 nan_a = _mm256_cmp_ps(ta, ta, _CMP_UNORD_Q), nan_b = _mm256_cmp_ps(tb, tb, _CMP_UNORD_Q);
      const __m256 near_a = _mm256_min_ps(_mm256_blendv_ps(ta, ninf, nan_a), _mm256_blendv_ps(tb, ninf, nan_b));
      __m256 far_a = _mm256_max_ps(_mm256_blendv_ps(ta, pinf, nan_a), _mm256_blendv_ps(tb, pinf, nan_b));
      far_a = _mm256_add_ps(far_a, _mm256_mul_ps(_mm256_andnot_ps(signmask, far_a), rel));  // Ize-style widening
      tnear = _mm256_max_ps(tnear, near_a);
      tfar = _mm256_min_ps(tfar, far_a);
    }
    int mask = _mm256_movemask_ps(_mm256_cmp_ps(tnear, tfar, _CMP_LE_OQ));
    if (len - chunk < 8) mask &= (1 << (len - chunk)) - 1;
    _mm256_store_ps(tn, tnear);
    while (mask) {
      const int b = __builtin_ctz(unsigned(mask));
      mask &= mask - 1;
      insert(chunk + b, tn[b]);
    }
  }
#else
  for (int k = 0; k < len; ++k) {
    float tnear = near, tfar = far;
    for (int a = 0; a < 3; ++a) {
      const float lo = codec.base(a) + float(c.boxes[a * len + k]) * codec.step(a) - codec.margin();
      const float hi = codec.base(a) + float(c.boxes[(3 + a) * len + k]) * codec.step(a) + codec.margin();
      const float ta = (lo - org[a]) * inv_dir[a], tb = (hi - org[a]) * inv_dir[a];
      const float near_a = std::fmin(std::isnan(ta) ? -INFINITY : ta, std::isnan(tb) ? -INFINITY : tb);
      float far_a = std::fmax(std::isnan(ta) ? INFINITY : ta, std::isnan(tb) ? INFINITY : tb);
      far_a += std::fabs(far_a) * kEntryFarWiden;
      tnear = std::fmax(tnear, near_a);
      tfar = std::fmin(tfar, far_a);
    }
    if (tnear <= tfar) insert(k, tnear);
  }
#endif
  return n;
}

}  // namespace rayscout::detail
