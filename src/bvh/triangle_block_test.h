// Watertight ray-triangle test of four or eight triangles at once (private SSE / AVX2 kernel).
#pragma once

#include <immintrin.h>

#include <cstdint>

#include "rayscout/bvh/wide_bvh.h"
#include "rayscout/core/triangle.h"

namespace rayscout::detail {

// The lane operations of the block test, for four lanes (one block) and eight (two). Spelled
// as intrinsics: the same kernel with GCC's vector operators on __m128 / __m256 compiled its
// comparisons to AVX-512 mask registers and traced 3-5 % slower.
struct Lanes4 {
  using F = __m128;
  static constexpr uint32_t kLanes = 4;
  static F load(const TriangleBlock* b, int vtx, int axis) { return _mm_load_ps(b->v[vtx][axis]); }
  static F normal(const TriangleBlock* b, int axis) { return _mm_load_ps(b->n[axis]); }
  static F low(__m128 x) { return x; }
#if defined(__AVX2__)
  static F low(__m256 x) { return _mm256_castps256_ps128(x); }
#endif
  static F set1(float x) { return _mm_set1_ps(x); }
  static F zero() { return _mm_setzero_ps(); }
  static F add(F a, F b) { return _mm_add_ps(a, b); }
  static F sub(F a, F b) { return _mm_sub_ps(a, b); }
  static F mul(F a, F b) { return _mm_mul_ps(a, b); }
  static F div(F a, F b) { return _mm_div_ps(a, b); }
  static F min(F a, F b) { return _mm_min_ps(a, b); }
  static F max(F a, F b) { return _mm_max_ps(a, b); }
  static F and_(F a, F b) { return _mm_and_ps(a, b); }
  static F or_(F a, F b) { return _mm_or_ps(a, b); }
  static F andnot(F a, F b) { return _mm_andnot_ps(a, b); }
  static F eq(F a, F b) { return _mm_cmpeq_ps(a, b); }
  static F neq(F a, F b) { return _mm_cmpneq_ps(a, b); }  // true for NaN
  static F lt(F a, F b) { return _mm_cmplt_ps(a, b); }
  static F gt(F a, F b) { return _mm_cmpgt_ps(a, b); }
  static F le(F a, F b) { return _mm_cmple_ps(a, b); }
  static F ge(F a, F b) { return _mm_cmpge_ps(a, b); }
  static uint32_t mask(F a) { return uint32_t(_mm_movemask_ps(a)); }
  static void store(float* p, F a) { _mm_store_ps(p, a); }
};

#if defined(__AVX2__)
struct Lanes8 {
  using F = __m256;
  static constexpr uint32_t kLanes = 8;
  // Lanes 0..3 from block b, 4..7 from block b + 1 (adjacent in memory).
  static F load(const TriangleBlock* b, int vtx, int axis) {
    return _mm256_set_m128(_mm_load_ps(b[1].v[vtx][axis]), _mm_load_ps(b[0].v[vtx][axis]));
  }
  static F normal(const TriangleBlock* b, int axis) {
    return _mm256_set_m128(_mm_load_ps(b[1].n[axis]), _mm_load_ps(b[0].n[axis]));
  }
  static F low(F x) { return x; }
  static F set1(float x) { return _mm256_set1_ps(x); }
  static F zero() { return _mm256_setzero_ps(); }
  static F add(F a, F b) { return _mm256_add_ps(a, b); }
  static F sub(F a, F b) { return _mm256_sub_ps(a, b); }
  static F mul(F a, F b) { return _mm256_mul_ps(a, b); }
  static F div(F a, F b) { return _mm256_div_ps(a, b); }
  static F min(F a, F b) { return _mm256_min_ps(a, b); }
  static F max(F a, F b) { return _mm256_max_ps(a, b); }
  static F and_(F a, F b) { return _mm256_and_ps(a, b); }
  static F or_(F a, F b) { return _mm256_or_ps(a, b); }
  static F andnot(F a, F b) { return _mm256_andnot_ps(a, b); }
  static F eq(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_EQ_OQ); }
  static F neq(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_NEQ_UQ); }  // true for NaN
  static F lt(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_LT_OQ); }
  static F gt(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_GT_OQ); }
  static F le(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_LE_OQ); }
  static F ge(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_GE_OQ); }
  static uint32_t mask(F a) { return uint32_t(_mm256_movemask_ps(a)); }
  static void store(float* p, F a) { _mm256_store_ps(p, a); }
};
#endif

/// The widest lanes a block test uses (two adjacent TriangleBlocks with AVX2, else one);
/// BlockRay<BlockTestLanes> serves every width.
#if defined(__AVX2__)
using BlockTestLanes = Lanes8;
#else
using BlockTestLanes = Lanes4;
#endif
/// Triangles one block test covers at most.
inline constexpr uint32_t kBlockTestLanes = BlockTestLanes::kLanes;

/// What a block test found: lanes hit within [tmin, tmax] and their t, plus the ev, ew, det
/// that give u = ev / det, v = ew / det exactly as core's intersect_triangle does. Lane l is
/// lane l % 4 of block l / 4 of the blocks tested.
struct BlockHits {
  uint32_t hit;       ///< lanes accepted by the single-precision test
  uint32_t fallback;  ///< lanes with an edge function exactly 0 or a NaN t: redo with intersect_triangle
  alignas(32) float t[kBlockTestLanes], ev[kBlockTestLanes], ew[kBlockTestLanes], det[kBlockTestLanes];
};

/// Per-ray constants of the block test in the lanes of L: core's RayPrecomp broadcast.
template <class L>
struct BlockRay {
  int kx, ky, kz;
  typename L::F ox, oy, oz, sx, sy, sz;  // origin components in kx, ky, kz order
  BlockRay(const Vec3& org, const RayPrecomp& rp)
      : kx(rp.kx), ky(rp.ky), kz(rp.kz),
        ox(L::set1(org[rp.kx])), oy(L::set1(org[rp.ky])), oz(L::set1(org[rp.kz])),
        sx(L::set1(rp.sx)), sy(L::set1(rp.sy)), sz(L::set1(rp.sz)) {}
};

/// Woop, Benthin, Wald 2013 (fig. 4) and core's plane_distance in the lanes of L: the same
/// float operations in the same order as core's intersect_triangle (compiled with
/// -ffp-contract=off), so every t, u, v is bit-identical. Lanes whose edge function is exactly
/// zero or whose t is NaN need the double-precision recomputations; they are reported in
/// `fallback` rather than handled here.
template <class L, class R>
inline void intersect_lanes(const TriangleBlock* b, uint32_t lanes, const BlockRay<R>& r, float tmin, float tmax,
                            BlockHits& out) {
  using F = typename L::F;
  // a = v0 - org per component, then the shear: ax = a[kx] - sx * a[kz].
  const F ox = L::low(r.ox), oy = L::low(r.oy), oz = L::low(r.oz);
  const F sx = L::low(r.sx), sy = L::low(r.sy), sz = L::low(r.sz);
  auto rel = [&](int vtx, int axis, F o) { return L::sub(L::load(b, vtx, axis), o); };
  const F a_x = rel(0, r.kx, ox), a_y = rel(0, r.ky, oy), a_z = rel(0, r.kz, oz);
  const F b_x = rel(1, r.kx, ox), b_y = rel(1, r.ky, oy), b_z = rel(1, r.kz, oz);
  const F c_x = rel(2, r.kx, ox), c_y = rel(2, r.ky, oy), c_z = rel(2, r.kz, oz);
  const F ax = L::sub(a_x, L::mul(sx, a_z)), ay = L::sub(a_y, L::mul(sy, a_z));
  const F bx = L::sub(b_x, L::mul(sx, b_z)), by = L::sub(b_y, L::mul(sy, b_z));
  const F cx = L::sub(c_x, L::mul(sx, c_z)), cy = L::sub(c_y, L::mul(sy, c_z));
  const F eu = L::sub(L::mul(cx, by), L::mul(cy, bx));
  const F ev = L::sub(L::mul(ax, cy), L::mul(ay, cx));
  const F ew = L::sub(L::mul(bx, ay), L::mul(by, ax));
  const F zero = L::zero();
  const F any_zero = L::or_(L::or_(L::eq(eu, zero), L::eq(ev, zero)), L::eq(ew, zero));
  const F any_neg = L::or_(L::or_(L::lt(eu, zero), L::lt(ev, zero)), L::lt(ew, zero));
  const F any_pos = L::or_(L::or_(L::gt(eu, zero), L::gt(ev, zero)), L::gt(ew, zero));
  const F det = L::add(L::add(eu, ev), ew);
  // Reject mixed edge signs and det == 0 (neq is true for NaN, as det == 0 is false).
  F ok = L::andnot(L::and_(any_neg, any_pos), L::neq(det, zero));
  const uint32_t zero_lanes = L::mask(any_zero) & lanes;
  // t in every test, with no branch on whether a lane passed the edge test: skipping it for
  // blocks without a candidate traced AO and diffuse rays 2-3 % slower (mispredictions; Zen 5,
  // session 51).
  const F az = L::mul(sz, a_z), bz = L::mul(sz, b_z), cz = L::mul(sz, c_z);
  // The block's normals (Triangle::normal) in the ray's (kx, ky, kz) order.
  const F nx = L::normal(b, r.kx), ny = L::normal(b, r.ky), nz = L::normal(b, r.kz);
  const F t = plane_distance<L>(nx, ny, nz, a_x, a_y, a_z, sx, sy, sz, az, bz, cz);
  const uint32_t redo = zero_lanes | (L::mask(L::and_(ok, L::neq(t, t))) & lanes);
  ok = L::and_(ok, L::and_(L::ge(t, L::set1(tmin)), L::le(t, L::set1(tmax))));
  out.fallback = redo;
  out.hit = L::mask(ok) & lanes & ~redo;
  L::store(out.t, t);
  L::store(out.ev, ev);
  L::store(out.ew, ew);
  L::store(out.det, det);
}

/// Tests the lanes set in `lanes` (bit l = lane l % 4 of block b[l / 4]; bits >= 4 only when
/// kBlockTestLanes is 8, and then b[1] must exist) in one pass: one block in four lanes, two
/// adjacent blocks in eight.
/// Always inlined: GCC 12 called it out of line from the traversal loop, 2-5 % slower.
[[gnu::always_inline]] inline void intersect_block(const TriangleBlock* b, uint32_t lanes,
                                                   const BlockRay<BlockTestLanes>& r, float tmin, float tmax,
                                                   BlockHits& out) {
#if defined(__AVX2__)
  if (lanes >> kTriangleBlockWidth) return intersect_lanes<Lanes8>(b, lanes, r, tmin, tmax, out);
#endif
  intersect_lanes<Lanes4>(b, lanes, r, tmin, tmax, out);
}

}  // namespace rayscout::detail
