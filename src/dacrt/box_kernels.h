// Ray-box kernels of DACRT: partitioning a ray index range against one box (AVX-512 or AVX2,
// with a scalar fallback) and the ray sampling of Algorithm 2: one sample ray against the
// K - 1 candidate box pairs (sample_pairs), or 16 sample rays against the two children of a
// chosen split (sample_children); plus the vote rules and the child order they decide.
// Both compute exactly core's intersect_box: the same float operations, near and far planes
// chosen by the sign of the inverse direction, the same NaN handling (tested lane by lane in
// tests/dacrt/dacrt_votes_test.cpp, rays lying in a box plane with a +-0 direction included).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cmath>
#include <cstring>
#include <limits>

#if defined(__AVX512F__) || defined(__AVX2__)
#include <immintrin.h>
#endif

#include "rayscout/core/triangle.h"
#include "rayscout/dacrt/dacrt_config.h"
#include "avx2_util.h"
#include "core/private/record_transpose.h"
#include "ray_record.h"

// g++ 12 reports a false "__Y may be used uninitialized" inside its own AVX-512 headers.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

namespace rayscout::dacrt {

/// Relative slack on the current hit distance when filtering. intersect_box keeps a box
/// entered at t_entry <= t, but a flat box (coplanar triangles) can compute its entry a few
/// ulps beyond the t its own triangle reports, which would cull an exact tie that the
/// smaller triangle id must win. Keeping boxes entered up to t (1 + 2^-12) makes filtering
/// conservative; the hit itself is always decided by intersect_triangle and is_closer.
inline constexpr float kHitSlack = 1.0f / 4096.0f;

/// A box grown by pad on every side: the absolute part of the same rounding (a ray leaving a
/// flat box's plane at t ~ 0; a hit t carries errors of the order of an ulp of the largest
/// coordinate involved, scene or ray origin). See pad_for().
inline Bounds3 padded(const Bounds3& b, float pad) { return {b.lo - Vec3(pad), b.hi + Vec3(pad)}; }

/// The padding for coordinates up to magnitude m: 2^-18 m, about 32 ulps.
inline float pad_for(float m) { return m * (1.0f / 262144.0f); }

/// The tmax used to filter a ray: t + |t| kHitSlack (never below t), and +inf for t = -inf,
/// as bvh's CullInterval::far: a hit at -inf (tmin = -inf) is an overflowed t, so the boxes
/// of triangles tied with it there (the smaller id wins) and, for tmax = -inf, every box must
/// stay in. NaN stays NaN.
inline float filter_tmax(float t) {
  const float grown = t + std::fabs(t) * kHitSlack;
  return t == -kInfinity ? kInfinity : (grown > t ? grown : t);
}

/// The tmin used to filter a ray: -inf for tmin = +inf (CullInterval::near; the mirror of
/// filter_tmax: a t overflowing to +inf). A retired
/// ray's NaN tmin stays NaN, which fails every box test.
inline float filter_tmin(float tmin) { return tmin == kInfinity ? -kInfinity : tmin; }

#if defined(__AVX512F__)
/// filter_tmin and filter_tmax in 16 lanes, one fixupimm each (token +inf -> -inf, token -inf
/// -> +inf; every other token keeps the first operand): the infinite cases cost one
/// instruction per limit. No max with t is needed: t + |t| kHitSlack >= t for every other t.
inline __m512 filter_tmin16(__m512 tmin) { return _mm512_fixupimm_ps(tmin, tmin, _mm512_set1_epi32(0x4 << 20), 0); }
inline __m512 filter_tmax16(__m512 t) {
  const __m512 grown = _mm512_add_ps(t, _mm512_mul_ps(_mm512_abs_ps(t), _mm512_set1_ps(kHitSlack)));
  return _mm512_fixupimm_ps(grown, t, _mm512_set1_epi32(0x5 << 16), 0);
}
#endif

/// intersect_box for one ray record against box with tmin = filter_tmin(tmin) and tmax =
/// filter_tmax(current t), so a box entered at or before the current hit (entry <= t) is kept.
inline bool ray_hits_box(const RayRecord& r, const Bounds3& box, float& tnear) {
  return intersect_box(Vec3(r.ox, r.oy, r.oz), Vec3(r.ix, r.iy, r.iz), box, filter_tmin(r.tmin), filter_tmax(r.t),
                       tnear);
}

/// As above, also giving the exit distance tfar (the tmax-clipped far end of the overlap).
inline bool ray_hits_box(const RayRecord& r, const Bounds3& box, float& tnear, float& tfar) {
  return intersect_box(Vec3(r.ox, r.oy, r.oz), Vec3(r.ix, r.iy, r.iz), box, filter_tmin(r.tmin), filter_tmax(r.t),
                       tnear, tfar);
}

/// Which child a sample ray votes for: 0 (left), 1 (right) or -1 (none), from whether it
/// hits each box (hl, hr), the entry (d) and exit (f) distances of the boxes it hits, and
/// its direction along the split axis (goes_up: left first). See DacrtConfig::votes.
inline int vote(DacrtVotes rule, bool hl, bool hr, float dl, float fl, float dr, float fr, bool goes_up) {
  if (rule == DacrtVotes::Literal) return (hl ? dl : kInfinity) < (hr ? dr : kInfinity) ? 0 : 1;
  if (!hl || !hr) return -1;
  switch (rule) {
    case DacrtVotes::Sign: return goes_up ? 0 : 1;
    case DacrtVotes::Interval: return fl < dr ? 0 : (fr < dl ? 1 : -1);
    default: return (dl < dr || (dl == dr && goes_up)) ? 0 : 1;  // DacrtVotes::Entry
  }
}

/// The child visited first, 0 (left) or 1 (right), from the votes n_L, n_R (not both 0) and
/// the children's triangle counts: the majority (Algorithm 1, line 18; a tie goes left), or
/// with depth_weighted the order of least expected waste, each child's votes weighed by the
/// depth log2(|T| + 1) of the subtree its voters would otherwise cross in vain first.
inline int first_child_by_votes(uint32_t n_l, uint32_t n_r, size_t tris_l, size_t tris_r, bool depth_weighted) {
  if (!depth_weighted) return n_l >= n_r ? 0 : 1;
  return double(n_l) * std::log2(double(tris_r) + 1.0) >= double(n_r) * std::log2(double(tris_l) + 1.0) ? 0 : 1;
}

#if defined(__AVX512F__)
/// One box against 16 rays, a RayRecord field per vector (f[0..7] as transpose_records16
/// gives them): ray_hits_box lane by lane, the same operations, the planes chosen by the
/// sign of each lane's inverse direction. Returns the hit lanes of valid; tnear and tfar
/// as ray_hits_box leaves them.
struct BoxX16 {
  __m512 lo[3], hi[3];
  explicit BoxX16(const Bounds3& b) {
    for (int a = 0; a < 3; ++a) { lo[a] = _mm512_set1_ps(b.lo[a]); hi[a] = _mm512_set1_ps(b.hi[a]); }
  }
  __mmask16 test(const __m512 (&f)[8], __mmask16 valid, __m512& tnear, __m512& tfar) const {
    const __m512 robust = _mm512_set1_ps(kSlabFarScale);
    const __m512i sign_bit = _mm512_set1_epi32(INT32_MIN);
    tnear = filter_tmin16(f[3]);
    tfar = filter_tmax16(f[7]);
    for (int a = 0; a < 3; ++a) {
      const __m512 o = f[a], inv = f[4 + a];
      const __m512 t0 = _mm512_mul_ps(_mm512_sub_ps(lo[a], o), inv);
      const __m512 t1 = _mm512_mul_ps(_mm512_sub_ps(hi[a], o), inv);
      const __mmask16 negative = _mm512_test_epi32_mask(_mm512_castps_si512(inv), sign_bit);
      const __m512 near = _mm512_mask_blend_ps(negative, t0, t1);
      const __m512 far = _mm512_mul_ps(_mm512_mask_blend_ps(negative, t1, t0), robust);
      tnear = _mm512_max_ps(near, tnear);  // near > tnear ? near : tnear, as the scalar test
      tfar = _mm512_min_ps(far, tfar);     // far < tfar ? far : tfar
    }
    return _mm512_mask_cmp_ps_mask(valid, tnear, tfar, _CMP_LE_OQ);
  }
};

/// vote() in 16 lanes: left and right get the lanes of valid that vote for each child, from
/// the hit masks hl, hr, the entry (d) and exit (f) distances and the lanes going up.
inline void vote_masks(DacrtVotes rule, __mmask16 valid, __mmask16 hl, __mmask16 hr, __m512 dl, __m512 fl, __m512 dr,
                       __m512 fr, __mmask16 up, __mmask16& left, __mmask16& right) {
  const __mmask16 both = hl & hr;
  if (rule == DacrtVotes::Literal) {  // (hl ? dl : inf) < (hr ? dr : inf)
    const __m512 inf = _mm512_set1_ps(kInfinity);
    left = _mm512_mask_cmp_ps_mask(valid, _mm512_mask_blend_ps(hl, inf, dl), _mm512_mask_blend_ps(hr, inf, dr),
                                   _CMP_LT_OQ);
    right = static_cast<__mmask16>(valid & ~left);
  } else if (rule == DacrtVotes::Sign) {
    left = both & up;
    right = static_cast<__mmask16>(both & ~up);
  } else if (rule == DacrtVotes::Interval) {
    left = _mm512_mask_cmp_ps_mask(both, fl, dr, _CMP_LT_OQ);
    right = static_cast<__mmask16>(_mm512_mask_cmp_ps_mask(both, fr, dl, _CMP_LT_OQ) & ~left);
  } else {
    left = _mm512_mask_cmp_ps_mask(both, dl, dr, _CMP_LT_OQ) | (_mm512_mask_cmp_ps_mask(both, dl, dr, _CMP_EQ_OQ) & up);
    right = static_cast<__mmask16>(both & ~left);
  }
}
#endif

/// Moves the ids of rays hitting box to the front of rid[0, n) and returns their count; the
/// others follow (the set is kept whole for the sibling). scratch holds >= n ids.
/// When prefetch is set, the entries prefetch[id] of the hitting rays are prefetched (the
/// shear records of a child that will be a leaf).
__attribute__((noinline)) inline size_t partition_rays(const RayRecord* rays, uint32_t* rid, size_t n, const Bounds3& box,
                             uint32_t* scratch, [[maybe_unused]] const RayShear* prefetch = nullptr) {
  size_t w = 0, m = 0, i = 0;
#if defined(__AVX512F__)
  const BoxX16 bx(box);
  const float* base = reinterpret_cast<const float*>(rays);
  auto test_fields = [&](const __m512 (&f)[8], __mmask16 valid) -> __mmask16 {
    __m512 tnear, tfar;
    return bx.test(f, valid, tnear, tfar);
  };
  // The tail: 8 gathers of the records' fields.
  auto test = [&](__m512i id, __mmask16 valid) -> __mmask16 {
    const __m512i off = _mm512_slli_epi32(id, 3);
    const __m512 z = _mm512_setzero_ps();
    __m512 f[8];
    for (int k = 0; k < 8; ++k) f[k] = _mm512_mask_i32gather_ps(z, valid, off, base + k, 4);
    return test_fields(f, valid);
  };
  // Full chunks: 16 records transposed into 8 field vectors, cheaper than 8 gathers.
  auto test_full = [&](const uint32_t* ids) -> __mmask16 {
    __m512 f[8];
    rayscout::detail::transpose_records16([&](int k) { return base + 8 * size_t(ids[k]); }, f);
    return test_fields(f, 0xFFFF);
  };
  constexpr size_t kAhead = 64;  // ids ahead whose records are prefetched: gathers then hit cache
  for (; i + 16 <= n; i += 16) {
    if (i + kAhead + 16 <= n)
      for (int k = 0; k < 16; k += 2) _mm_prefetch(reinterpret_cast<const char*>(rays + rid[i + kAhead + k]), _MM_HINT_T0);
    const __m512i id = _mm512_loadu_si512(rid + i);
    const __mmask16 hit = test_full(rid + i);
    // Full-width stores of the compressed ids: w, m <= i, so they end inside the chunk just
    // loaded (never past ids not yet read, never past the end of scratch).
    _mm512_storeu_si512(rid + w, _mm512_maskz_compress_epi32(hit, id));
    _mm512_storeu_si512(scratch + m, _mm512_maskz_compress_epi32(static_cast<__mmask16>(~hit), id));
    const int h = __builtin_popcount(hit);
    if (prefetch)
      for (int q = 0; q < h; ++q) _mm_prefetch(reinterpret_cast<const char*>(prefetch + rid[w + q]), _MM_HINT_T0);
    w += h;
    m += 16 - h;
  }
  if (i < n) {
    const __mmask16 valid = static_cast<__mmask16>((1u << (n - i)) - 1u);
    const __m512i id = _mm512_maskz_loadu_epi32(valid, rid + i);
    const __mmask16 hit = test(id, valid);
    _mm512_mask_compressstoreu_epi32(rid + w, hit, id);
    _mm512_mask_compressstoreu_epi32(scratch + m, static_cast<__mmask16>(valid & ~hit), id);
    const int h = __builtin_popcount(hit);
    w += h;
    m += (n - i) - h;
    i = n;
  }
#elif defined(__AVX2__)
  const __m256 lox = _mm256_set1_ps(box.lo.x), loy = _mm256_set1_ps(box.lo.y), loz = _mm256_set1_ps(box.lo.z);
  const __m256 hix = _mm256_set1_ps(box.hi.x), hiy = _mm256_set1_ps(box.hi.y), hiz = _mm256_set1_ps(box.hi.z);
  const __m256 robust = _mm256_set1_ps(kSlabFarScale), slack = _mm256_set1_ps(kHitSlack);
  const __m256 abs_mask = _mm256_castsi256_ps(_mm256_set1_epi32(0x7FFFFFFF));
  const __m256 pinf = _mm256_set1_ps(kInfinity), ninf = _mm256_set1_ps(-kInfinity);
  const float* base = reinterpret_cast<const float*>(rays);
  constexpr size_t kAhead = 32;
  for (; i + 8 <= n; i += 8) {
    if (i + kAhead + 8 <= n)
      for (int k = 0; k < 8; k += 2) _mm_prefetch(reinterpret_cast<const char*>(rays + rid[i + kAhead + k]), _MM_HINT_T0);
    const __m256i id = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(rid + i));
    const __m256i off = _mm256_slli_epi32(id, 3);
    const __m256 ox = _mm256_i32gather_ps(base + 0, off, 4), oy = _mm256_i32gather_ps(base + 1, off, 4);
    const __m256 oz = _mm256_i32gather_ps(base + 2, off, 4);
    const __m256 tmin = _mm256_i32gather_ps(base + 3, off, 4);
    const __m256 ix = _mm256_i32gather_ps(base + 4, off, 4), iy = _mm256_i32gather_ps(base + 5, off, 4);
    const __m256 iz = _mm256_i32gather_ps(base + 6, off, 4), t = _mm256_i32gather_ps(base + 7, off, 4);
    __m256 tnear = _mm256_blendv_ps(tmin, ninf, _mm256_cmp_ps(tmin, pinf, _CMP_EQ_OQ));  // filter_tmin
    __m256 tfar = _mm256_add_ps(t, _mm256_mul_ps(_mm256_and_ps(t, abs_mask), slack));  // filter_tmax
    tfar = _mm256_blendv_ps(_mm256_max_ps(tfar, t), pinf, _mm256_cmp_ps(t, ninf, _CMP_EQ_OQ));
    avx2::slab(lox, hix, ox, ix, robust, tnear, tfar);
    avx2::slab(loy, hiy, oy, iy, robust, tnear, tfar);
    avx2::slab(loz, hiz, oz, iz, robust, tnear, tfar);
    const int hit = _mm256_movemask_ps(_mm256_cmp_ps(tnear, tfar, _CMP_LE_OQ));
    // Full-width stores of the packed ids: w, m <= i, so they end inside the chunk just read.
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(rid + w), avx2::compress(id, hit));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(scratch + m), avx2::compress(id, ~hit & 0xFF));
    const int h = __builtin_popcount(unsigned(hit));
    if (prefetch)
      for (int q = 0; q < h; ++q) _mm_prefetch(reinterpret_cast<const char*>(prefetch + rid[w + q]), _MM_HINT_T0);
    w += h;
    m += 8 - h;
  }
#endif
  for (; i < n; ++i) {
    float tnear;
    const uint32_t id = rid[i];
    if (ray_hits_box(rays[id], box, tnear)) rid[w++] = id;
    else scratch[m++] = id;
  }
  std::memcpy(rid + w, scratch, m * sizeof(uint32_t));
  return w;
}

/// Candidate boxes as structure of arrays, padded to a multiple of 16.
struct BoxSoa {
  static constexpr int kMax = 256;
  alignas(64) float lox[kMax], loy[kMax], loz[kMax], hix[kMax], hiy[kMax], hiz[kMax];
  int count = 0;  ///< a multiple of 16; unused lanes hold empty boxes
  /// Sets n boxes' storage to empty and count to n rounded up to 16.
  void resize(int n) {
    count = (n + 15) & ~15;
    for (int i = n; i < count; ++i) set(i, Bounds3{});
  }
  void set(int i, const Bounds3& b) {
    lox[i] = b.lo.x; loy[i] = b.lo.y; loz[i] = b.lo.z; hix[i] = b.hi.x; hiy[i] = b.hi.y; hiz[i] = b.hi.z;
  }
};

/// Algorithm 2 for one sample ray against the candidate pairs (lb[j], rb[j]): c_L, c_R count
/// the boxes hit, n_L, n_R the votes by `rule` (see vote()). Padding lanes hold empty boxes;
/// they count no hits (a literal vote of theirs goes to n_R, unread).
inline void sample_pairs(const RayRecord& r, const BoxSoa& lb, const BoxSoa& rb, bool goes_up, DacrtVotes rule,
                         uint32_t* c_l, uint32_t* c_r, uint32_t* votes_l, uint32_t* votes_r) {
#if defined(__AVX512F__)
  const __m512 ox = _mm512_set1_ps(r.ox), oy = _mm512_set1_ps(r.oy), oz = _mm512_set1_ps(r.oz);
  const __m512 ix = _mm512_set1_ps(r.ix), iy = _mm512_set1_ps(r.iy), iz = _mm512_set1_ps(r.iz);
  const __m512 robust = _mm512_set1_ps(kSlabFarScale), tmin = _mm512_set1_ps(filter_tmin(r.tmin)),
               tmax = _mm512_set1_ps(filter_tmax(r.t));
  const __m512i one = _mm512_set1_epi32(1);
  // One ray for all boxes: its near and far planes are chosen once, by the sign of its inverse
  // direction, by swapping the plane arrays.
  const bool nx = std::signbit(r.ix), ny = std::signbit(r.iy), nz = std::signbit(r.iz);
  auto test = [&](const BoxSoa& b, int i, __m512& tnear, __m512& tfar) {
    tnear = tmin;
    tfar = tmax;
    auto slab = [&](const float* near, const float* far, __m512 o, __m512 inv) {
      const __m512 a = _mm512_mul_ps(_mm512_sub_ps(_mm512_load_ps(near + i), o), inv);
      const __m512 c = _mm512_mul_ps(_mm512_mul_ps(_mm512_sub_ps(_mm512_load_ps(far + i), o), inv), robust);
      tnear = _mm512_max_ps(a, tnear);  // a > tnear ? a : tnear, as the scalar test
      tfar = _mm512_min_ps(c, tfar);    // c < tfar ? c : tfar
    };
    slab(nx ? b.hix : b.lox, nx ? b.lox : b.hix, ox, ix);
    slab(ny ? b.hiy : b.loy, ny ? b.loy : b.hiy, oy, iy);
    slab(nz ? b.hiz : b.loz, nz ? b.loz : b.hiz, oz, iz);
    return _mm512_cmp_ps_mask(tnear, tfar, _CMP_LE_OQ);
  };
  for (int i = 0; i < lb.count; i += 16) {
    __m512 nl, nr, fl, fr;
    const __mmask16 hl = test(lb, i, nl, fl), hr = test(rb, i, nr, fr);
    __mmask16 left, right;  // padding lanes hit nothing; a literal vote of theirs goes to n_R, unread
    vote_masks(rule, 0xFFFF, hl, hr, nl, fl, nr, fr, goes_up ? 0xFFFF : 0, left, right);
    auto add = [&](uint32_t* p, __mmask16 m) {
      __m512i v = _mm512_load_si512(p + i);
      _mm512_store_si512(p + i, _mm512_mask_add_epi32(v, m, v, one));
    };
    add(c_l, hl);
    add(c_r, hr);
    add(votes_l, left);
    add(votes_r, right);
  }
#elif defined(__AVX2__)
  const __m256 ox = _mm256_set1_ps(r.ox), oy = _mm256_set1_ps(r.oy), oz = _mm256_set1_ps(r.oz);
  const __m256 ix = _mm256_set1_ps(r.ix), iy = _mm256_set1_ps(r.iy), iz = _mm256_set1_ps(r.iz);
  const __m256 robust = _mm256_set1_ps(kSlabFarScale), tmin = _mm256_set1_ps(filter_tmin(r.tmin)),
               tmax = _mm256_set1_ps(filter_tmax(r.t));
  // Returns the hit mask as all-ones lanes.
  auto test = [&](const BoxSoa& b, int i, __m256& tnear, __m256& tfar) {
    tnear = tmin;
    tfar = tmax;
    avx2::slab(_mm256_load_ps(b.lox + i), _mm256_load_ps(b.hix + i), ox, ix, robust, tnear, tfar);
    avx2::slab(_mm256_load_ps(b.loy + i), _mm256_load_ps(b.hiy + i), oy, iy, robust, tnear, tfar);
    avx2::slab(_mm256_load_ps(b.loz + i), _mm256_load_ps(b.hiz + i), oz, iz, robust, tnear, tfar);
    return _mm256_cmp_ps(tnear, tfar, _CMP_LE_OQ);
  };
  const __m256 up = goes_up ? _mm256_castsi256_ps(_mm256_set1_epi32(-1)) : _mm256_setzero_ps();
  for (int i = 0; i < lb.count; i += 8) {
    __m256 nl, nr, fl, fr;
    const __m256 hl = test(lb, i, nl, fl), hr = test(rb, i, nr, fr);
    const __m256 both = _mm256_and_ps(hl, hr);
    __m256 left, right;
    if (rule == DacrtVotes::Literal) {
      left = _mm256_or_ps(_mm256_andnot_ps(hr, hl), _mm256_and_ps(both, _mm256_cmp_ps(nl, nr, _CMP_LT_OQ)));
      right = _mm256_andnot_ps(left, _mm256_castsi256_ps(_mm256_set1_epi32(-1)));
    } else if (rule == DacrtVotes::Sign) {
      left = _mm256_and_ps(both, up);
      right = _mm256_andnot_ps(left, both);
    } else if (rule == DacrtVotes::Interval) {
      left = _mm256_and_ps(both, _mm256_cmp_ps(fl, nr, _CMP_LT_OQ));
      right = _mm256_andnot_ps(left, _mm256_and_ps(both, _mm256_cmp_ps(fr, nl, _CMP_LT_OQ)));
    } else {
      left = _mm256_and_ps(both, _mm256_or_ps(_mm256_cmp_ps(nl, nr, _CMP_LT_OQ),
                                              _mm256_and_ps(up, _mm256_cmp_ps(nl, nr, _CMP_EQ_OQ))));
      right = _mm256_andnot_ps(left, both);
    }
    // An all-ones lane is -1: subtracting it counts one.
    auto add = [&](uint32_t* p, __m256 m) {
      __m256i* q = reinterpret_cast<__m256i*>(p + i);
      _mm256_store_si256(q, _mm256_sub_epi32(_mm256_load_si256(q), _mm256_castps_si256(m)));
    };
    add(c_l, hl);
    add(c_r, hr);
    add(votes_l, left);
    add(votes_r, right);
  }
#else
  for (int j = 0; j < lb.count; ++j) {
    const Bounds3 bl{{lb.lox[j], lb.loy[j], lb.loz[j]}, {lb.hix[j], lb.hiy[j], lb.hiz[j]}};
    const Bounds3 br{{rb.lox[j], rb.loy[j], rb.loz[j]}, {rb.hix[j], rb.hiy[j], rb.hiz[j]}};
    float dl, fl, dr, fr;
    const bool hl = ray_hits_box(r, bl, dl, fl), hr = ray_hits_box(r, br, dr, fr);
    c_l[j] += hl;
    c_r[j] += hr;
    const int v = vote(rule, hl, hr, dl, fl, dr, fr, goes_up);
    if (v == 0) ++votes_l[j]; else if (v == 1) ++votes_r[j];
  }
#endif
}

/// Algorithm 2 for the two children of a chosen split: hits[c] counts the sample rays
/// rays[id(q)], q < ns, that hit box[c], votes[c] their votes by rule (see vote(); goes_up
/// along axis). Sample ids are read in order q = 0, 1, ... (a random strategy draws them so).
/// With AVX-512 16 sample rays per box test, each lane as the scalar loop below.
template <class SampleId>
inline void sample_children(const RayRecord* rays, size_t ns, SampleId id, const Bounds3 (&box)[2], int axis,
                            DacrtVotes rule, uint32_t (&hits)[2], uint32_t (&votes)[2]) {
  hits[0] = hits[1] = votes[0] = votes[1] = 0;
  size_t q = 0;
#if defined(__AVX512F__)
  const BoxX16 bl(box[0]), br(box[1]);
  const float* base = reinterpret_cast<const float*>(rays);
  for (; q < ns; q += 16) {
    const int n = int(std::min<size_t>(16, ns - q));
    uint32_t ids[16];
    for (int k = 0; k < n; ++k) ids[k] = uint32_t(id(q + k));
    for (int k = n; k < 16; ++k) ids[k] = ids[0];  // lanes outside valid: any record
    const __mmask16 valid = static_cast<__mmask16>((1u << n) - 1u);
    __m512 f[8];
    rayscout::detail::transpose_records16([&](int k) { return base + 8 * size_t(ids[k]); }, f);
    __m512 dl, fl, dr, fr;
    const __mmask16 hl = bl.test(f, valid, dl, fl), hr = br.test(f, valid, dr, fr);
    const __mmask16 up = _mm512_cmp_ps_mask(f[4 + axis], _mm512_setzero_ps(), _CMP_GE_OQ);  // RayRecord::goes_up
    __mmask16 left, right;
    vote_masks(rule, valid, hl, hr, dl, fl, dr, fr, up, left, right);
    hits[0] += uint32_t(__builtin_popcount(hl));
    hits[1] += uint32_t(__builtin_popcount(hr));
    votes[0] += uint32_t(__builtin_popcount(left));
    votes[1] += uint32_t(__builtin_popcount(right));
  }
#endif
  for (; q < ns; ++q) {
    const RayRecord& r = rays[id(q)];
    float d[2], f[2];
    bool h[2];
    for (int c = 0; c < 2; ++c) {
      h[c] = ray_hits_box(r, box[c], d[c], f[c]);
      hits[c] += h[c];
    }
    const int v = vote(rule, h[0], h[1], d[0], f[0], d[1], f[1], r.goes_up(axis));
    if (v >= 0) ++votes[v];
  }
}

}  // namespace rayscout::dacrt

#pragma GCC diagnostic pop
