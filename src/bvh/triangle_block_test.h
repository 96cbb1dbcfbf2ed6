// Watertight ray-triangle test of four triangles at once (private SSE kernel).
#pragma once

#include <immintrin.h>

#include <cstdint>

#include "rayscout/bvh/wide_bvh.h"
#include "rayscout/core/triangle.h"

namespace rayscout::detail {

/// Per-ray constants of the block test: core's RayPrecomp broadcast to four lanes.
struct BlockRay {
  int kx, ky, kz;
  __m128 ox, oy, oz, sx, sy, sz;  // origin components in kx, ky, kz order
  BlockRay(const Vec3& org, const RayPrecomp& rp)
      : kx(rp.kx), ky(rp.ky), kz(rp.kz),
        ox(_mm_set1_ps(org[rp.kx])), oy(_mm_set1_ps(org[rp.ky])), oz(_mm_set1_ps(org[rp.kz])),
        sx(_mm_set1_ps(rp.sx)), sy(_mm_set1_ps(rp.sy)), sz(_mm_set1_ps(rp.sz)) {}
};

/// What a block test found: lanes hit within [tmin, tmax] and their t, plus the ev, ew, det
/// that give u = ev / det, v = ew / det exactly as core's intersect_triangle does.
struct BlockHits {
  uint32_t hit;       ///< lanes accepted by the single-precision test
  uint32_t fallback;  ///< lanes with an edge function exactly 0: redo with intersect_triangle
  alignas(16) float t[4], ev[4], ew[4], det[4];
};

/// Woop, Benthin, Wald 2013 (fig. 4) in four lanes: the same float operations in the same
/// order as core's intersect_triangle (compiled with -ffp-contract=off), so every t, u, v is
/// bit-identical. Lanes whose edge function is exactly zero need the double-precision
/// recomputation; they are reported in `fallback` rather than handled here.
inline void intersect_block(const TriangleBlock& b, uint32_t lanes, const BlockRay& r, float tmin, float tmax,
                            BlockHits& out) {
  auto load = [&](int vtx, int axis) { return _mm_load_ps(b.v[vtx][axis]); };
  // a = v0 - org per component, then the shear: ax = a[kx] - sx * a[kz].
  const __m128 a_x = _mm_sub_ps(load(0, r.kx), r.ox), a_y = _mm_sub_ps(load(0, r.ky), r.oy),
               a_z = _mm_sub_ps(load(0, r.kz), r.oz);
  const __m128 b_x = _mm_sub_ps(load(1, r.kx), r.ox), b_y = _mm_sub_ps(load(1, r.ky), r.oy),
               b_z = _mm_sub_ps(load(1, r.kz), r.oz);
  const __m128 c_x = _mm_sub_ps(load(2, r.kx), r.ox), c_y = _mm_sub_ps(load(2, r.ky), r.oy),
               c_z = _mm_sub_ps(load(2, r.kz), r.oz);
  const __m128 ax = _mm_sub_ps(a_x, _mm_mul_ps(r.sx, a_z)), ay = _mm_sub_ps(a_y, _mm_mul_ps(r.sy, a_z));
  const __m128 bx = _mm_sub_ps(b_x, _mm_mul_ps(r.sx, b_z)), by = _mm_sub_ps(b_y, _mm_mul_ps(r.sy, b_z));
  const __m128 cx = _mm_sub_ps(c_x, _mm_mul_ps(r.sx, c_z)), cy = _mm_sub_ps(c_y, _mm_mul_ps(r.sy, c_z));
  const __m128 eu = _mm_sub_ps(_mm_mul_ps(cx, by), _mm_mul_ps(cy, bx));
  const __m128 ev = _mm_sub_ps(_mm_mul_ps(ax, cy), _mm_mul_ps(ay, cx));
  const __m128 ew = _mm_sub_ps(_mm_mul_ps(bx, ay), _mm_mul_ps(by, ax));
  const __m128 zero = _mm_setzero_ps();
  const __m128 any_zero = _mm_or_ps(_mm_or_ps(_mm_cmpeq_ps(eu, zero), _mm_cmpeq_ps(ev, zero)), _mm_cmpeq_ps(ew, zero));
  const __m128 any_neg = _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(eu, zero), _mm_cmplt_ps(ev, zero)), _mm_cmplt_ps(ew, zero));
  const __m128 any_pos = _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(eu, zero), _mm_cmpgt_ps(ev, zero)), _mm_cmpgt_ps(ew, zero));
  const __m128 det = _mm_add_ps(_mm_add_ps(eu, ev), ew);
  const __m128 az = _mm_mul_ps(r.sz, a_z), bz = _mm_mul_ps(r.sz, b_z), cz = _mm_mul_ps(r.sz, c_z);
  const __m128 t = _mm_div_ps(
      _mm_add_ps(_mm_add_ps(_mm_mul_ps(eu, az), _mm_mul_ps(ev, bz)), _mm_mul_ps(ew, cz)), det);
  // Reject mixed edge signs and det == 0 (cmpneq is true for NaN, as det == 0 is false).
  __m128 ok = _mm_andnot_ps(_mm_and_ps(any_neg, any_pos), _mm_cmpneq_ps(det, zero));
  ok = _mm_and_ps(ok, _mm_and_ps(_mm_cmpge_ps(t, _mm_set1_ps(tmin)), _mm_cmple_ps(t, _mm_set1_ps(tmax))));
  const uint32_t zero_lanes = uint32_t(_mm_movemask_ps(any_zero)) & lanes;
  out.fallback = zero_lanes;
  out.hit = uint32_t(_mm_movemask_ps(ok)) & lanes & ~zero_lanes;
  _mm_store_ps(out.t, t);
  _mm_store_ps(out.ev, ev);
  _mm_store_ps(out.ew, ew);
  _mm_store_ps(out.det, det);
}

}  // namespace rayscout::detail
