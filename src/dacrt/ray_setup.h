// Per-call ray setup of DACRT: RayRecord, RayShear and the identity id array for a range of
// a RayBatch, 16 rays at a time with AVX-512 (the same divisions as core's RayPrecomp, so
// the constants are bit-identical), plus the largest origin coordinate magnitude.
#pragma once

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstddef>
#include <cstdint>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

#include "rayscout/core/ray.h"
#include "ray_record.h"

// g++ 12 reports a false "__Y may be used uninitialized" inside its own AVX-512 headers.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"

namespace rayscout::dacrt {

/// Scalar setup of ray i (the reference the SIMD path reproduces).
inline void setup_ray(const RayBatch& rays, size_t i, RayRecord* rec, RayShear* shear) {
  const RayPrecomp p(Vec3(rays.dx[i], rays.dy[i], rays.dz[i]));
  rec[i] = {rays.ox[i], rays.oy[i], rays.oz[i], rays.tmin[i], p.inv_dir.x, p.inv_dir.y, p.inv_dir.z, rays.tmax[i]};
  shear[i] = shear_of(p);
}

/// Fills rec, shear and rid (= i) for rays [begin, end); returns max |origin coordinate|
/// over them (0 for none). Infinite and NaN coordinates are left out: such rays miss (their
/// direction is NaN, see Accelerator::intersect), and an infinite padding would keep every
/// ray in every box.
inline float setup_rays(const RayBatch& rays, size_t begin, size_t end, RayRecord* rec, RayShear* shear,
                        uint32_t* rid) {
  size_t i = begin;
  float magnitude = 0.0f;
#if defined(__AVX512F__)
  const __m512 one = _mm512_set1_ps(1.0f), zero = _mm512_setzero_ps(), flt_max = _mm512_set1_ps(FLT_MAX);
  __m512 mag = zero;
  const __m512i lo_lanes = _mm512_setr_epi32(0, 1, 2, 3, 16, 17, 18, 19, 8, 9, 10, 11, 24, 25, 26, 27);
  const __m512i hi_lanes = _mm512_setr_epi32(4, 5, 6, 7, 20, 21, 22, 23, 12, 13, 14, 15, 28, 29, 30, 31);
  const __m512i pair_lo = _mm512_setr_epi32(0, 1, 2, 3, 16, 17, 18, 19, 4, 5, 6, 7, 20, 21, 22, 23);
  const __m512i pair_hi = _mm512_setr_epi32(8, 9, 10, 11, 24, 25, 26, 27, 12, 13, 14, 15, 28, 29, 30, 31);
  const __m512i step = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  for (; i + 16 <= end; i += 16) {
    const __m512 ox = _mm512_loadu_ps(rays.ox.data() + i), oy = _mm512_loadu_ps(rays.oy.data() + i);
    const __m512 oz = _mm512_loadu_ps(rays.oz.data() + i), tmin = _mm512_loadu_ps(rays.tmin.data() + i);
    const __m512 dx = _mm512_loadu_ps(rays.dx.data() + i), dy = _mm512_loadu_ps(rays.dy.data() + i);
    const __m512 dz = _mm512_loadu_ps(rays.dz.data() + i), tmax = _mm512_loadu_ps(rays.tmax.data() + i);
    for (const __m512 o : {ox, oy, oz}) {
      const __m512 a = _mm512_abs_ps(o);
      mag = _mm512_mask_max_ps(mag, _mm512_cmp_ps_mask(a, flt_max, _CMP_LE_OQ), a, mag);  // finite only
    }
    // RayPrecomp: kz = max_axis(|d|), kx, ky the next axes, swapped when d[kz] < 0.
    const __m512 ax = _mm512_abs_ps(dx), ay = _mm512_abs_ps(dy), az = _mm512_abs_ps(dz);
    const __mmask16 xy = _mm512_cmp_ps_mask(ax, ay, _CMP_GE_OQ), xz = _mm512_cmp_ps_mask(ax, az, _CMP_GE_OQ),
                    yz = _mm512_cmp_ps_mask(ay, az, _CMP_GE_OQ);
    const __mmask16 z0 = xy & xz, z1 = static_cast<__mmask16>(~xy & yz);  // kz = 0, kz = 1, else 2
    const __m512 dkz = _mm512_mask_blend_ps(z0, _mm512_mask_blend_ps(z1, dz, dy), dx);
    __m512 dkx = _mm512_mask_blend_ps(z0, _mm512_mask_blend_ps(z1, dx, dz), dy);  // kx = kz + 1 mod 3
    __m512 dky = _mm512_mask_blend_ps(z0, _mm512_mask_blend_ps(z1, dy, dx), dz);  // ky = kx + 1 mod 3
    __m512i kz = _mm512_mask_blend_epi32(z0, _mm512_mask_blend_epi32(z1, _mm512_set1_epi32(2), _mm512_set1_epi32(1)),
                                         _mm512_setzero_si512());
    __m512i kx = _mm512_mask_blend_epi32(z0, _mm512_mask_blend_epi32(z1, _mm512_setzero_si512(), _mm512_set1_epi32(2)),
                                         _mm512_set1_epi32(1));
    __m512i ky = _mm512_mask_blend_epi32(z0, _mm512_mask_blend_epi32(z1, _mm512_set1_epi32(1), _mm512_setzero_si512()),
                                         _mm512_set1_epi32(2));
    const __mmask16 neg = _mm512_cmp_ps_mask(dkz, zero, _CMP_LT_OQ);
    const __m512 tx = dkx;
    dkx = _mm512_mask_blend_ps(neg, dkx, dky);
    dky = _mm512_mask_blend_ps(neg, dky, tx);
    const __m512i tk = kx;
    kx = _mm512_mask_blend_epi32(neg, kx, ky);
    ky = _mm512_mask_blend_epi32(neg, ky, tk);
    const __m512 sx = _mm512_div_ps(dkx, dkz), sy = _mm512_div_ps(dky, dkz), sz = _mm512_div_ps(one, dkz);
    const __m512i k = _mm512_or_si512(kx, _mm512_or_si512(_mm512_slli_epi32(ky, 8), _mm512_slli_epi32(kz, 16)));
    const __m512 ix = _mm512_div_ps(one, dx), iy = _mm512_div_ps(one, dy), iz = _mm512_div_ps(one, dz);

    // Records: 8 field vectors -> 16 consecutive 32-byte records (an 8x16 transpose).
    const __m512 f[8] = {ox, oy, oz, tmin, ix, iy, iz, tmax};
    __m512 s[8];
    for (int q = 0; q < 4; ++q) {
      s[q] = _mm512_permutex2var_ps(f[q], lo_lanes, f[q + 4]);
      s[q + 4] = _mm512_permutex2var_ps(f[q], hi_lanes, f[q + 4]);
    }
    float* out = reinterpret_cast<float*>(rec + i);
    for (int q = 0; q < 2; ++q) {  // 4x4 transposes inside each 128-bit lane
      const __m512 t0 = _mm512_unpacklo_ps(s[4 * q], s[4 * q + 1]), t1 = _mm512_unpackhi_ps(s[4 * q], s[4 * q + 1]);
      const __m512 t2 = _mm512_unpacklo_ps(s[4 * q + 2], s[4 * q + 3]), t3 = _mm512_unpackhi_ps(s[4 * q + 2], s[4 * q + 3]);
      const __m512 r[4] = {_mm512_shuffle_ps(t0, t2, 0x44), _mm512_shuffle_ps(t0, t2, 0xEE), _mm512_shuffle_ps(t1, t3, 0x44),
                           _mm512_shuffle_ps(t1, t3, 0xEE)};
      for (int j = 0; j < 4; ++j) {  // r[j] = record 4q + j (low half), 4q + j + 8 (high half)
        _mm256_storeu_ps(out + 8 * (4 * q + j), _mm512_castps512_ps256(r[j]));
        _mm256_storeu_ps(out + 8 * (4 * q + j + 8), _mm512_extractf32x8_ps(r[j], 1));
      }
    }
    // Shears: 4 field vectors -> 16 consecutive 16-byte records.
    const __m512 kf = _mm512_castsi512_ps(k);
    const __m512 t0 = _mm512_unpacklo_ps(sx, sy), t1 = _mm512_unpackhi_ps(sx, sy);
    const __m512 t2 = _mm512_unpacklo_ps(sz, kf), t3 = _mm512_unpackhi_ps(sz, kf);
    const __m512 o0 = _mm512_shuffle_ps(t0, t2, 0x44), o1 = _mm512_shuffle_ps(t0, t2, 0xEE);
    const __m512 o2 = _mm512_shuffle_ps(t1, t3, 0x44), o3 = _mm512_shuffle_ps(t1, t3, 0xEE);
    const __m512 a = _mm512_permutex2var_ps(o0, pair_lo, o1), b = _mm512_permutex2var_ps(o2, pair_lo, o3);
    const __m512 c = _mm512_permutex2var_ps(o0, pair_hi, o1), d = _mm512_permutex2var_ps(o2, pair_hi, o3);
    float* sh = reinterpret_cast<float*>(shear + i);
    _mm512_storeu_ps(sh + 0, _mm512_shuffle_f32x4(a, b, 0x44));
    _mm512_storeu_ps(sh + 16, _mm512_shuffle_f32x4(a, b, 0xEE));
    _mm512_storeu_ps(sh + 32, _mm512_shuffle_f32x4(c, d, 0x44));
    _mm512_storeu_ps(sh + 48, _mm512_shuffle_f32x4(c, d, 0xEE));
    _mm512_storeu_si512(rid + i, _mm512_add_epi32(_mm512_set1_epi32(int(i)), step));
  }
  magnitude = _mm512_reduce_max_ps(mag);
#endif
  for (; i < end; ++i) {
    setup_ray(rays, i, rec, shear);
    rid[i] = uint32_t(i);
    for (const float o : {rays.ox[i], rays.oy[i], rays.oz[i]})
      if (std::fabs(o) <= FLT_MAX) magnitude = std::max(magnitude, std::fabs(o));
  }
  return magnitude;
}

}  // namespace rayscout::dacrt

#pragma GCC diagnostic pop
