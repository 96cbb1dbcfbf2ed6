// AVX-512 leaf kernel: 16 rays against one triangle at a time, the same float operations in
// the same order as core's intersect_triangle (watertight, Woop et al. 2013, with core's
// plane_distance), so hits are bit-identical; lanes with an exactly-zero edge function or a
// NaN t take the scalar path (its double recomputations).
#pragma once

#if defined(__AVX512F__)

#include <immintrin.h>

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>

#include "leaf_kernels.h"
#include "ray_record.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

namespace rayscout::dacrt {

/// intersect_triangle's edge functions, determinant and sign decision for 16 lanes of sheared
/// vertices a, b, c: of the lanes in `lanes`, those with an exactly-zero edge function
/// (zero_edge: they take the scalar path) and those that may hit (candidates).
struct EdgeTest {
  __m512 eu, ev, ew, det;
  __mmask16 zero_edge, candidates;
};
inline EdgeTest edge_test(__mmask16 lanes, __m512 ax, __m512 ay, __m512 bx, __m512 by, __m512 cx, __m512 cy) {
  const __m512 zero = _mm512_setzero_ps();
  EdgeTest e;
  e.eu = _mm512_sub_ps(_mm512_mul_ps(cx, by), _mm512_mul_ps(cy, bx));
  e.ev = _mm512_sub_ps(_mm512_mul_ps(ax, cy), _mm512_mul_ps(ay, cx));
  e.ew = _mm512_sub_ps(_mm512_mul_ps(bx, ay), _mm512_mul_ps(by, ax));
  e.zero_edge = lanes & (_mm512_cmp_ps_mask(e.eu, zero, _CMP_EQ_OQ) | _mm512_cmp_ps_mask(e.ev, zero, _CMP_EQ_OQ) |
                         _mm512_cmp_ps_mask(e.ew, zero, _CMP_EQ_OQ));
  const __mmask16 neg = _mm512_cmp_ps_mask(e.eu, zero, _CMP_LT_OQ) | _mm512_cmp_ps_mask(e.ev, zero, _CMP_LT_OQ) |
                        _mm512_cmp_ps_mask(e.ew, zero, _CMP_LT_OQ);
  const __mmask16 pos = _mm512_cmp_ps_mask(e.eu, zero, _CMP_GT_OQ) | _mm512_cmp_ps_mask(e.ev, zero, _CMP_GT_OQ) |
                        _mm512_cmp_ps_mask(e.ew, zero, _CMP_GT_OQ);
  e.det = _mm512_add_ps(_mm512_add_ps(e.eu, e.ev), e.ew);
  e.candidates = lanes & ~e.zero_edge & ~(neg & pos) & _mm512_cmp_ps_mask(e.det, zero, _CMP_NEQ_UQ);
  return e;
}

/// The lane operations of core's plane_distance in 16 lanes.
struct Lanes16 {
  using F = __m512;
  static F add(F a, F b) { return _mm512_add_ps(a, b); }
  static F mul(F a, F b) { return _mm512_mul_ps(a, b); }
  static F div(F a, F b) { return _mm512_div_ps(a, b); }
  static F min(F a, F b) { return _mm512_min_ps(a, b); }
  static F max(F a, F b) { return _mm512_max_ps(a, b); }
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
  const __m512 zero = _mm512_setzero_ps();
  const __m512i izero = _mm512_setzero_si512(), ione = _mm512_set1_epi32(1);
  uint64_t tests = 0;
  for (size_t i = 0; i < nr; i += 16) {
    const __mmask16 valid = nr - i >= 16 ? __mmask16(0xFFFF) : __mmask16((1u << (nr - i)) - 1u);
    const __m512i id = _mm512_maskz_loadu_epi32(valid, rid + i);
    const __m512i off8 = _mm512_slli_epi32(id, 3);
    const __m512i off4 = _mm512_slli_epi32(id, 2);
    const __m512 ox = _mm512_mask_i32gather_ps(zero, valid, off8, rbase + 0, 4);
    const __m512 oy = _mm512_mask_i32gather_ps(zero, valid, off8, rbase + 1, 4);
    const __m512 oz = _mm512_mask_i32gather_ps(zero, valid, off8, rbase + 2, 4);
    const __m512 tmin = _mm512_mask_i32gather_ps(zero, valid, off8, rbase + 3, 4);
    __m512 best_t = _mm512_mask_i32gather_ps(zero, valid, off8, rbase + 7, 4);
    const __m512i kk = _mm512_mask_i32gather_epi32(izero, valid, off4, pibase + 3, 4);
    const __m512i byte = _mm512_set1_epi32(0xFF);
    const __m512i kx = _mm512_and_si512(kk, byte), ky = _mm512_and_si512(_mm512_srli_epi32(kk, 8), byte);
    const __m512i kz = _mm512_srli_epi32(kk, 16);
    const __m512 sx = _mm512_mask_i32gather_ps(zero, valid, off4, pbase + 0, 4);
    const __m512 sy = _mm512_mask_i32gather_ps(zero, valid, off4, pbase + 1, 4);
    const __m512 sz = _mm512_mask_i32gather_ps(zero, valid, off4, pbase + 2, 4);
    // The current closest triangle id matters only for exact ties (is_closer), so it is read
    // lazily, for the lanes that need it (a cold random read per ray otherwise).
    __m512i best_p = izero;
    __mmask16 p_known = 0;
    auto need_p = [&](__mmask16 m) {
      m = static_cast<__mmask16>(m & ~p_known);
      if (!m) return;
      best_p = _mm512_mask_i32gather_epi32(best_p, m, id, reinterpret_cast<const int*>(out.prim), 4);
      p_known |= m;
    };
    __m512 best_u = zero, best_v = zero;
    __mmask16 changed = 0;
    // Retired any-hit rays (NaN tmin: see retire()) cost no tests, as in the scalar kernel.
    const __mmask16 retired = kAny ? _mm512_cmp_ps_mask(tmin, tmin, _CMP_UNORD_Q) : 0;
    __mmask16 active = static_cast<__mmask16>(valid & ~retired);
    const __mmask16 x0 = _mm512_cmpeq_epi32_mask(kx, izero), x1 = _mm512_cmpeq_epi32_mask(kx, ione);
    const __mmask16 y0 = _mm512_cmpeq_epi32_mask(ky, izero), y1 = _mm512_cmpeq_epi32_mask(ky, ione);
    const __mmask16 z0 = _mm512_cmpeq_epi32_mask(kz, izero), z1 = _mm512_cmpeq_epi32_mask(kz, ione);
    auto pick = [](__mmask16 m0, __mmask16 m1, __m512 x, __m512 y, __m512 z) {
      return _mm512_mask_blend_ps(m0, _mm512_mask_blend_ps(m1, z, y), x);
    };
    // Vertex w relative to the origin in the ray's sheared frame: w[kx] - sx w[kz], ...
    auto rel_any = [&](const Vec3& w, __m512& rx, __m512& ry, __m512& rz) {
      const __m512 wx = _mm512_sub_ps(_mm512_set1_ps(w.x), ox);
      const __m512 wy = _mm512_sub_ps(_mm512_set1_ps(w.y), oy);
      const __m512 wz = _mm512_sub_ps(_mm512_set1_ps(w.z), oz);
      const __m512 k = pick(z0, z1, wx, wy, wz);
      rx = _mm512_sub_ps(pick(x0, x1, wx, wy, wz), _mm512_mul_ps(sx, k));
      ry = _mm512_sub_ps(pick(y0, y1, wx, wy, wz), _mm512_mul_ps(sy, k));
      rz = _mm512_mul_ps(sz, k);
    };
    // The same when every lane has the same axes (kx, ky, kz) (coherent rays, the common
    // case): the axes are picked once per group, not per triangle and lane.
    const uint32_t k0 = uint32_t(_mm_cvtsi128_si32(_mm512_castsi512_si128(kk)));
    const bool uniform = _mm512_mask_cmpneq_epi32_mask(valid, kk, _mm512_set1_epi32(int(k0))) == 0;
    const int ua = int(k0 & 0xFF), ub = int((k0 >> 8) & 0xFF), uc = int(k0 >> 16);
    static_assert(sizeof(Vec3) == 3 * sizeof(float), "w[a] reads Vec3 as float[3]");
    const __m512 org[3] = {ox, oy, oz};
    const __m512 oa = org[ua], ob = org[ub], oc = org[uc];
    auto rel_uniform = [&](const Vec3& w, __m512& rx, __m512& ry, __m512& rz) {
      const float* wp = &w.x;
      const __m512 k = _mm512_sub_ps(_mm512_set1_ps(wp[uc]), oc);
      rx = _mm512_sub_ps(_mm512_sub_ps(_mm512_set1_ps(wp[ua]), oa), _mm512_mul_ps(sx, k));
      ry = _mm512_sub_ps(_mm512_sub_ps(_mm512_set1_ps(wp[ub]), ob), _mm512_mul_ps(sy, k));
      rz = _mm512_mul_ps(sz, k);
    };
    // plane_distance for triangle tri, in the frames of rel_any and rel_uniform.
    auto distance_any = [&](const Triangle& tri, __m512 az, __m512 bz, __m512 cz) {
      const Vec3 n = tri.normal();
      const __m512 wx = _mm512_sub_ps(_mm512_set1_ps(tri.v0.x), ox);
      const __m512 wy = _mm512_sub_ps(_mm512_set1_ps(tri.v0.y), oy);
      const __m512 wz = _mm512_sub_ps(_mm512_set1_ps(tri.v0.z), oz);
      const __m512 nx = _mm512_set1_ps(n.x), ny = _mm512_set1_ps(n.y), nz = _mm512_set1_ps(n.z);
      return plane_distance<Lanes16>(pick(x0, x1, nx, ny, nz), pick(y0, y1, nx, ny, nz), pick(z0, z1, nx, ny, nz),
                              pick(x0, x1, wx, wy, wz), pick(y0, y1, wx, wy, wz), pick(z0, z1, wx, wy, wz), sx, sy,
                              sz, az, bz, cz);
    };
    auto distance_uniform = [&](const Triangle& tri, __m512 az, __m512 bz, __m512 cz) {
      const Vec3 n = tri.normal();
      const float *np = &n.x, *wp = &tri.v0.x;
      return plane_distance<Lanes16>(_mm512_set1_ps(np[ua]), _mm512_set1_ps(np[ub]), _mm512_set1_ps(np[uc]),
                              _mm512_sub_ps(_mm512_set1_ps(wp[ua]), oa), _mm512_sub_ps(_mm512_set1_ps(wp[ub]), ob),
                              _mm512_sub_ps(_mm512_set1_ps(wp[uc]), oc), sx, sy, sz, az, bz, cz);
    };
    auto triangles = [&](auto rel, auto distance) {
      for (size_t j = 0; j < nt && active; ++j) {
        const uint32_t p = tid[j];
        const Triangle& tri = tris[p];
        tests += uint64_t(__builtin_popcount(active));
        __m512 ax, ay, az, bx, by, bz, cx, cy, cz;
        rel(tri.v0, ax, ay, az);
        rel(tri.v1, bx, by, bz);
        rel(tri.v2, cx, cy, cz);
        const EdgeTest e = edge_test(active, ax, ay, bx, by, cx, cy);
        __mmask16 redo = e.zero_edge, hit = e.candidates;  // redo: the scalar path decides
        __m512 tt = zero, u = zero, v = zero;
        if (hit) {
          tt = distance(tri, az, bz, cz);
          redo |= hit & _mm512_cmp_ps_mask(tt, tt, _CMP_UNORD_Q);  // a NaN t: see intersect_triangle
          hit &= _mm512_cmp_ps_mask(tt, tmin, _CMP_GE_OQ) & _mm512_cmp_ps_mask(tt, best_t, _CMP_LE_OQ);
          if (!kAny) {
            // is_closer: nearer, or equally near with a smaller triangle id.
            const __mmask16 nearer = _mm512_cmp_ps_mask(tt, best_t, _CMP_LT_OQ);
            const __mmask16 equal = hit & _mm512_cmp_ps_mask(tt, best_t, _CMP_EQ_OQ);
            need_p(equal);
            const __mmask16 tie = equal & _mm512_cmplt_epu32_mask(_mm512_set1_epi32(int(p)), best_p);
            hit &= nearer | tie;
            u = _mm512_div_ps(e.ev, e.det);
            v = _mm512_div_ps(e.ew, e.det);
          }
        }
        if (redo) {
          if (!kAny) need_p(redo);
          LeafLanes<16> lane;
          _mm512_store_ps(lane.t, tt); _mm512_store_ps(lane.u, u); _mm512_store_ps(lane.v, v);
          _mm512_store_ps(lane.best_t, best_t); _mm512_store_ps(lane.tmin, tmin);
          _mm512_store_ps(lane.ox, ox); _mm512_store_ps(lane.oy, oy); _mm512_store_ps(lane.oz, oz);
          _mm512_store_si512(lane.id, id); _mm512_store_si512(lane.best_p, best_p);
          hit |= __mmask16(redo_in_scalar<kAny>(lane, redo, tri, p, pre));
          tt = _mm512_load_ps(lane.t); u = _mm512_load_ps(lane.u); v = _mm512_load_ps(lane.v);
        }
        if (!hit) continue;
        if (kAny) {
          active &= ~hit;
          changed |= hit;
        } else {
          best_t = _mm512_mask_blend_ps(hit, best_t, tt);
          best_u = _mm512_mask_blend_ps(hit, best_u, u);
          best_v = _mm512_mask_blend_ps(hit, best_v, v);
          best_p = _mm512_mask_blend_epi32(hit, best_p, _mm512_set1_epi32(int(p)));
          p_known |= hit;
          changed |= hit;
        }
      }
    };
    if (uniform) triangles(rel_uniform, distance_uniform);
    else triangles(rel_any, distance_any);
    if (!changed) continue;
    LeafLanes<16> lane;
    _mm512_store_ps(lane.best_t, best_t); _mm512_store_ps(lane.u, best_u); _mm512_store_ps(lane.v, best_v);
    _mm512_store_si512(lane.id, id); _mm512_store_si512(lane.best_p, best_p);
    store_leaf_hits<kAny>(lane, changed, rays, out, occ);
  }
  return tests;
}

/// Fewer rays than a ray group (nr < 16) against a node's triangles: 16 triangles per test, the
/// rays one after another, the same float operations as leaf_simd with ray and triangle
/// swapped, so hits are bit-identical to the scalar kernels. A ray's closest hit among a
/// group's lanes is their least (t, id), which is where the scalar kernel's run of is_closer
/// updates ends; tests are counted as the scalar kernels count them (an any-hit ray up to its
/// first hit in triangle order).
template <bool kAny>
__attribute__((noinline)) uint64_t leaf_few_rays(RayRecord* rays, const RayShear* pre, const uint32_t* rid, size_t nr,
                                                 const Triangle* tris, const uint32_t* tid, size_t nt, HitOut out,
                                                 uint8_t* occ) {
  static_assert(sizeof(Triangle) == 9 * sizeof(float), "a triangle is gathered as 9 floats");
  struct Best {
    float t, u, v;
    uint32_t p;
    bool changed;
  } best[16];
  for (size_t i = 0; i < nr; ++i) best[i] = {rays[rid[i]].t, 0.0f, 0.0f, kAny ? 0u : out.prim[rid[i]], false};
  const float* base = reinterpret_cast<const float*>(tris);
  const __m512 zero = _mm512_setzero_ps();
  uint64_t tests = 0;
  for (size_t j = 0; j < nt; j += 16) {
    const size_t n = std::min<size_t>(16, nt - j);
    const __mmask16 valid = n == 16 ? __mmask16(0xFFFF) : __mmask16((1u << n) - 1u);
    const __m512i p = _mm512_maskz_loadu_epi32(valid, tid + j);
    const __m512i off = _mm512_mullo_epi32(p, _mm512_set1_epi32(9));
    __m512 w[3][3];  // w[vertex][axis] of the 16 triangles
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a) w[k][a] = _mm512_mask_i32gather_ps(zero, valid, off, base + 3 * k + a, 4);
    // Their normals (v1 - v0) x (v2 - v0), as Triangle::normal.
    __m512 e1[3], e2[3];
    for (int a = 0; a < 3; ++a) e1[a] = _mm512_sub_ps(w[1][a], w[0][a]), e2[a] = _mm512_sub_ps(w[2][a], w[0][a]);
    const __m512 nrm[3] = {_mm512_sub_ps(_mm512_mul_ps(e1[1], e2[2]), _mm512_mul_ps(e1[2], e2[1])),
                           _mm512_sub_ps(_mm512_mul_ps(e1[2], e2[0]), _mm512_mul_ps(e1[0], e2[2])),
                           _mm512_sub_ps(_mm512_mul_ps(e1[0], e2[1]), _mm512_mul_ps(e1[1], e2[0]))};
    for (size_t i = 0; i < nr; ++i) {
      const uint32_t r = rid[i];
      if (kAny && occ[r]) continue;  // retired: no tests, as in the scalar kernel
      RayRecord& ray = rays[r];
      const RayShear& sh = pre[r];
      const int kx = int(sh.k & 0xFF), ky = int((sh.k >> 8) & 0xFF), kz = int(sh.k >> 16);
      const float o[3] = {ray.ox, ray.oy, ray.oz};
      const __m512 sx = _mm512_set1_ps(sh.sx), sy = _mm512_set1_ps(sh.sy), sz = _mm512_set1_ps(sh.sz);
      // Vertex k relative to the origin in the ray's sheared frame (intersect_triangle's a, b, c).
      auto rel = [&](int k, __m512& rx, __m512& ry, __m512& rz) {
        const __m512 c = _mm512_sub_ps(w[k][kz], _mm512_set1_ps(o[kz]));
        rx = _mm512_sub_ps(_mm512_sub_ps(w[k][kx], _mm512_set1_ps(o[kx])), _mm512_mul_ps(sx, c));
        ry = _mm512_sub_ps(_mm512_sub_ps(w[k][ky], _mm512_set1_ps(o[ky])), _mm512_mul_ps(sy, c));
        rz = _mm512_mul_ps(sz, c);
      };
      __m512 ax, ay, az, bx, by, bz, cx, cy, cz;
      rel(0, ax, ay, az);
      rel(1, bx, by, bz);
      rel(2, cx, cy, cz);
      const EdgeTest e = edge_test(valid, ax, ay, bx, by, cx, cy);
      __mmask16 redo = e.zero_edge, hit = e.candidates;  // redo: the scalar path decides
      alignas(64) float t[16], u[16], v[16];
      if (hit) {
        auto a0 = [&](int axis) { return _mm512_sub_ps(w[0][axis], _mm512_set1_ps(o[axis])); };
        const __m512 tt = plane_distance<Lanes16>(nrm[kx], nrm[ky], nrm[kz], a0(kx), a0(ky), a0(kz), sx, sy, sz, az, bz, cz);
        redo |= hit & _mm512_cmp_ps_mask(tt, tt, _CMP_UNORD_Q);
        hit &= _mm512_cmp_ps_mask(tt, _mm512_set1_ps(ray.tmin), _CMP_GE_OQ) &
               _mm512_cmp_ps_mask(tt, _mm512_set1_ps(best[i].t), _CMP_LE_OQ);
        _mm512_store_ps(t, tt);
        if (!kAny) {
          _mm512_store_ps(u, _mm512_div_ps(e.ev, e.det));
          _mm512_store_ps(v, _mm512_div_ps(e.ew, e.det));
        }
      }
      // Exactly-zero edge functions and NaN t: core's test (its double recomputations), lane by lane.
      for (uint32_t z = redo; z; z &= z - 1) {
        const int l = std::countr_zero(z);
        if (intersect_triangle(Vec3(o[0], o[1], o[2]), to_precomp(sh), tris[tid[j + size_t(l)]], ray.tmin, best[i].t,
                               t[l], u[l], v[l]))
          hit |= __mmask16(1u << l);
      }
      if (kAny) {
        if (!hit) {
          tests += n;
          continue;
        }
        tests += uint64_t(std::countr_zero(uint32_t(hit))) + 1;
        occ[r] = 1;
        retire(ray);
        continue;
      }
      tests += n;
      if (!hit) continue;
      // The least (t, id) of the hit lanes; its own t keeps the sign of a zero.
      const __m512 tv = _mm512_load_ps(t);
      const __mmask16 nearest = hit & _mm512_cmp_ps_mask(tv, _mm512_set1_ps(_mm512_mask_reduce_min_ps(hit, tv)), _CMP_EQ_OQ);
      const uint32_t p_min = _mm512_mask_reduce_min_epu32(nearest, p);
      const int l = std::countr_zero(uint32_t(nearest & _mm512_cmpeq_epi32_mask(p, _mm512_set1_epi32(int(p_min)))));
      if (is_closer(t[l], p_min, best[i].t, best[i].p)) best[i] = {t[l], u[l], v[l], p_min, true};
    }
  }
  if (!kAny)
    for (size_t i = 0; i < nr; ++i)
      if (best[i].changed) {
        const uint32_t r = rid[i];
        rays[r].t = best[i].t; out.prim[r] = best[i].p; out.u[r] = best[i].u; out.v[r] = best[i].v;
      }
  return tests;
}

}  // namespace rayscout::dacrt

#pragma GCC diagnostic pop

#endif  // __AVX512F__
