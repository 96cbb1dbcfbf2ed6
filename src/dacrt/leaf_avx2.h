// AVX2 leaf kernel (when AVX-512 is not available): 8 rays against one triangle at a time,
// the same float operations in the same order as core's intersect_triangle (watertight,
// Woop et al. 2013, with core's plane_distance) and leaf_avx512.h, so hits are bit-identical;
// lanes with an exactly-zero edge function or a NaN t take the scalar path (its double
// recomputations).
#pragma once

#if defined(__AVX2__) && !defined(__AVX512F__)

#include <immintrin.h>

#include <cstddef>
#include <cstdint>

#include "leaf_kernels.h"
#include "ray_record.h"

namespace rayscout::dacrt {

/// The lane operations of core's plane_distance in 8 lanes.
struct Lanes8 {
  using F = __m256;
  static F add(F a, F b) { return _mm256_add_ps(a, b); }
  static F mul(F a, F b) { return _mm256_mul_ps(a, b); }
  static F div(F a, F b) { return _mm256_div_ps(a, b); }
  static F min(F a, F b) { return _mm256_min_ps(a, b); }
  static F max(F a, F b) { return _mm256_max_ps(a, b); }
};

/// kAny = false: closest hit (updates t in rays and out.prim/u/v). kAny = true: any hit
/// (marks occ and retires). Returns ray-triangle tests, counted as the scalar kernels do.
template <bool kAny>
__attribute__((noinline)) uint64_t leaf_simd(RayRecord* rays, const RayShear* pre, const uint32_t* rid, size_t nr,
                                             const Triangle* tris, const uint32_t* tid, size_t nt, HitOut out,
                                             uint8_t* occ) {
  const float* rbase = reinterpret_cast<const float*>(rays);
  const float* pbase = reinterpret_cast<const float*>(pre);
  const int* pibase = reinterpret_cast<const int*>(pre);
  const __m256 zero = _mm256_setzero_ps();
  const __m256i izero = _mm256_setzero_si256(), ione = _mm256_set1_epi32(1);
  const __m256i sign = _mm256_set1_epi32(int(0x80000000u));
  auto mask_of = [](int bits) {  // lane mask bits -> all-ones lanes
    const __m256i lane = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    return _mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(bits), lane), lane));
  };
  uint64_t tests = 0;
  for (size_t i = 0; i < nr; i += 8) {
    const int valid = nr - i >= 8 ? 0xFF : int((1u << (nr - i)) - 1u);
    const __m256 vmask = mask_of(valid);
    alignas(32) uint32_t ids[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    for (int l = 0; l < 8; ++l)
      if ((valid >> l) & 1) ids[l] = rid[i + l];
    const __m256i id = _mm256_load_si256(reinterpret_cast<const __m256i*>(ids));
    const __m256i off8 = _mm256_slli_epi32(id, 3);
    const __m256i off4 = _mm256_slli_epi32(id, 2);
    auto gf = [&](const float* b, __m256i off) { return _mm256_mask_i32gather_ps(zero, b, off, vmask, 4); };
    auto gi = [&](const int* b, __m256i off) {
      return _mm256_mask_i32gather_epi32(izero, b, off, _mm256_castps_si256(vmask), 4);
    };
    const __m256 ox = gf(rbase + 0, off8), oy = gf(rbase + 1, off8), oz = gf(rbase + 2, off8);
    const __m256 tmin = gf(rbase + 3, off8);
    __m256 best_t = gf(rbase + 7, off8);
    const __m256i kk = gi(pibase + 3, off4), byte = _mm256_set1_epi32(0xFF);
    const __m256i kx = _mm256_and_si256(kk, byte), ky = _mm256_and_si256(_mm256_srli_epi32(kk, 8), byte);
    const __m256i kz = _mm256_srli_epi32(kk, 16);
    const __m256 sx = gf(pbase + 0, off4), sy = gf(pbase + 1, off4), sz = gf(pbase + 2, off4);
    __m256i best_p = kAny ? izero : gi(reinterpret_cast<const int*>(out.prim), id);
    __m256 best_u = zero, best_v = zero;
    int changed = 0;
    // Retired any-hit rays (NaN tmin: see retire()) cost no tests, as in the scalar kernel.
    int active = kAny ? valid & ~_mm256_movemask_ps(_mm256_cmp_ps(tmin, tmin, _CMP_UNORD_Q)) : valid;
    const __m256 x0 = _mm256_castsi256_ps(_mm256_cmpeq_epi32(kx, izero)), x1 = _mm256_castsi256_ps(_mm256_cmpeq_epi32(kx, ione));
    const __m256 y0 = _mm256_castsi256_ps(_mm256_cmpeq_epi32(ky, izero)), y1 = _mm256_castsi256_ps(_mm256_cmpeq_epi32(ky, ione));
    const __m256 z0 = _mm256_castsi256_ps(_mm256_cmpeq_epi32(kz, izero)), z1 = _mm256_castsi256_ps(_mm256_cmpeq_epi32(kz, ione));
    auto pick = [](__m256 m0, __m256 m1, __m256 x, __m256 y, __m256 z) {
      return _mm256_blendv_ps(_mm256_blendv_ps(z, y, m1), x, m0);
    };
    for (size_t j = 0; j < nt && active; ++j) {
      const uint32_t p = tid[j];
      const Triangle& tri = tris[p];
      tests += uint64_t(__builtin_popcount(unsigned(active)));
      auto rel = [&](const Vec3& w, __m256& rx, __m256& ry, __m256& rz) {
        const __m256 wx = _mm256_sub_ps(_mm256_set1_ps(w.x), ox);
        const __m256 wy = _mm256_sub_ps(_mm256_set1_ps(w.y), oy);
        const __m256 wz = _mm256_sub_ps(_mm256_set1_ps(w.z), oz);
        const __m256 k = pick(z0, z1, wx, wy, wz);
        rx = _mm256_sub_ps(pick(x0, x1, wx, wy, wz), _mm256_mul_ps(sx, k));
        ry = _mm256_sub_ps(pick(y0, y1, wx, wy, wz), _mm256_mul_ps(sy, k));
        rz = _mm256_mul_ps(sz, k);
      };
      __m256 ax, ay, az, bx, by, bz, cx, cy, cz;
      rel(tri.v0, ax, ay, az);
      rel(tri.v1, bx, by, bz);
      rel(tri.v2, cx, cy, cz);
      const __m256 eu = _mm256_sub_ps(_mm256_mul_ps(cx, by), _mm256_mul_ps(cy, bx));
      const __m256 ev = _mm256_sub_ps(_mm256_mul_ps(ax, cy), _mm256_mul_ps(ay, cx));
      const __m256 ew = _mm256_sub_ps(_mm256_mul_ps(bx, ay), _mm256_mul_ps(by, ax));
      auto bits = [](__m256 m) { return _mm256_movemask_ps(m); };
      int redo = active & (bits(_mm256_cmp_ps(eu, zero, _CMP_EQ_OQ)) | bits(_mm256_cmp_ps(ev, zero, _CMP_EQ_OQ)) |
                           bits(_mm256_cmp_ps(ew, zero, _CMP_EQ_OQ)));
      const int neg = bits(_mm256_cmp_ps(eu, zero, _CMP_LT_OQ)) | bits(_mm256_cmp_ps(ev, zero, _CMP_LT_OQ)) |
                      bits(_mm256_cmp_ps(ew, zero, _CMP_LT_OQ));
      const int pos = bits(_mm256_cmp_ps(eu, zero, _CMP_GT_OQ)) | bits(_mm256_cmp_ps(ev, zero, _CMP_GT_OQ)) |
                      bits(_mm256_cmp_ps(ew, zero, _CMP_GT_OQ));
      const __m256 det = _mm256_add_ps(_mm256_add_ps(eu, ev), ew);
      int hit = active & ~redo & ~(neg & pos) & bits(_mm256_cmp_ps(det, zero, _CMP_NEQ_UQ));
      __m256 tt = zero, u = zero, v = zero;
      if (hit) {
        // core's plane_distance: the normal and v0 - org picked in the ray's (kx, ky, kz) order.
        const Vec3 n = tri.normal();
        const __m256 nx = _mm256_set1_ps(n.x), ny = _mm256_set1_ps(n.y), nz = _mm256_set1_ps(n.z);
        const __m256 wx = _mm256_sub_ps(_mm256_set1_ps(tri.v0.x), ox);
        const __m256 wy = _mm256_sub_ps(_mm256_set1_ps(tri.v0.y), oy);
        const __m256 wz = _mm256_sub_ps(_mm256_set1_ps(tri.v0.z), oz);
        tt = plane_distance<Lanes8>(pick(x0, x1, nx, ny, nz), pick(y0, y1, nx, ny, nz), pick(z0, z1, nx, ny, nz),
                                    pick(x0, x1, wx, wy, wz), pick(y0, y1, wx, wy, wz), pick(z0, z1, wx, wy, wz), sx,
                                    sy, sz, az, bz, cz);
        redo |= hit & bits(_mm256_cmp_ps(tt, tt, _CMP_UNORD_Q));  // a NaN t: see intersect_triangle
        hit &= bits(_mm256_cmp_ps(tt, tmin, _CMP_GE_OQ)) & bits(_mm256_cmp_ps(tt, best_t, _CMP_LE_OQ));
        if (!kAny) {
          // is_closer: nearer, or equally near with a smaller triangle id (unsigned compare).
          const int nearer = bits(_mm256_cmp_ps(tt, best_t, _CMP_LT_OQ));
          const __m256i smaller = _mm256_cmpgt_epi32(_mm256_xor_si256(best_p, sign),
                                                     _mm256_xor_si256(_mm256_set1_epi32(int(p)), sign));
          const int tie = bits(_mm256_cmp_ps(tt, best_t, _CMP_EQ_OQ)) & bits(_mm256_castsi256_ps(smaller));
          hit &= nearer | tie;
          u = _mm256_div_ps(ev, det);
          v = _mm256_div_ps(ew, det);
        }
      }
      if (redo) {  // exactly-zero edge functions and NaN t: the scalar path decides
        LeafLanes<8> lane;
        _mm256_store_ps(lane.t, tt); _mm256_store_ps(lane.u, u); _mm256_store_ps(lane.v, v);
        _mm256_store_ps(lane.best_t, best_t); _mm256_store_ps(lane.tmin, tmin);
        _mm256_store_ps(lane.ox, ox); _mm256_store_ps(lane.oy, oy); _mm256_store_ps(lane.oz, oz);
        _mm256_store_si256(reinterpret_cast<__m256i*>(lane.id), id);
        _mm256_store_si256(reinterpret_cast<__m256i*>(lane.best_p), best_p);
        hit |= int(redo_in_scalar<kAny>(lane, uint32_t(redo), tri, p, pre));
        tt = _mm256_load_ps(lane.t); u = _mm256_load_ps(lane.u); v = _mm256_load_ps(lane.v);
      }
      if (!hit) continue;
      changed |= hit;
      if (kAny) {
        active &= ~hit;
      } else {
        const __m256 hm = mask_of(hit);
        best_t = _mm256_blendv_ps(best_t, tt, hm);
        best_u = _mm256_blendv_ps(best_u, u, hm);
        best_v = _mm256_blendv_ps(best_v, v, hm);
        best_p = _mm256_castps_si256(_mm256_blendv_ps(_mm256_castsi256_ps(best_p),
                                                      _mm256_castsi256_ps(_mm256_set1_epi32(int(p))), hm));
      }
    }
    if (!changed) continue;
    LeafLanes<8> lane;
    _mm256_store_ps(lane.best_t, best_t); _mm256_store_ps(lane.u, best_u); _mm256_store_ps(lane.v, best_v);
    _mm256_store_si256(reinterpret_cast<__m256i*>(lane.id), id);
    _mm256_store_si256(reinterpret_cast<__m256i*>(lane.best_p), best_p);
    store_leaf_hits<kAny>(lane, uint32_t(changed), rays, out, occ);
  }
  return tests;
}

}  // namespace rayscout::dacrt

#endif  // __AVX2__ && !__AVX512F__
