// Robust slab tests (private): one box; with SIMD, the 8 child boxes of a WideNode and a
// group of Bvh2 nodes (a seeded traversal's start entries).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "rayscout/bvh/bvh2.h"
#include "rayscout/bvh/wide_bvh.h"
#include "core/private/record_transpose.h"
#include "rayscout/core/triangle.h"

#if defined(__AVX2__)
#include <immintrin.h>
#endif

namespace rayscout::detail {

// The far-distance scale of core's intersect_box (Ize 2013): 1 + 2 gamma(3) ...
inline constexpr float kRobustScale = kSlabFarScale;
// ... and its mirror for a negative far distance, which must move towards zero to stay
// conservative (traversal widens tmin below 0, see CullInterval).
inline constexpr float kRobustScaleNegative = 2.0f - kRobustScale;

/// The slab test of core's intersect_box (Ize 2013): near and far planes chosen by the sign
/// of the inverse direction (not by comparing the two distances, as Ize's paper and Embree
/// do, which can cull a box when a 0 direction puts the origin's 0 * inf = NaN on a plane),
/// NaN leaving the axis unconstrained. One difference: a negative far distance is scaled by
/// kRobustScaleNegative, towards zero, so this test keeps every box core's keeps (and a few
/// more), which the widened tmin of CullInterval needs.
inline bool intersect_box_robust(const Vec3& org, const Vec3& inv_dir, const Bounds3& box, float tmin,
                                 float tmax, float& tnear_out) {
  float tnear = tmin, tfar = tmax;
  for (int axis = 0; axis < 3; ++axis) {
    const bool neg = std::signbit(inv_dir[axis]);
    const float t0 = ((neg ? box.hi : box.lo)[axis] - org[axis]) * inv_dir[axis];
    float t1 = ((neg ? box.lo : box.hi)[axis] - org[axis]) * inv_dir[axis];
    t1 *= std::signbit(t1) ? kRobustScaleNegative : kRobustScale;
    tnear = t0 > tnear ? t0 : tnear;  // NaN t0 keeps tnear
    tfar = t1 < tfar ? t1 : tfar;     // NaN t1 keeps tfar
  }
  tnear_out = tnear;
  return tnear <= tfar;
}

// The SIMD kernels below write the rest of the slab step out, each in its own loop: folding
// it into one inline function for all of them made GCC 12 emit different instructions for
// these loops (compared by disassembly; not timed).
#if defined(__AVX2__)
/// Distances along the ray to the planes x[axis] = plane in each lane, for the ray's origin
/// o and inverse direction inv on that axis (broadcast): (plane - o) * inv.
inline __m256 plane_distance(__m256 plane, __m256 o, __m256 inv) { return _mm256_mul_ps(_mm256_sub_ps(plane, o), inv); }
#endif

/// Per-ray constants of the wide box test: the broadcast origin, inverse direction and tmin,
/// and per axis the byte offsets of the near and far plane arrays inside a WideNode.
struct WideRay {
#if defined(__AVX2__)
  __m256 ox, oy, oz, ix, iy, iz, tmin8;
#endif
  Vec3 org, inv_dir;
  float tmin;
  size_t near_off[3], far_off[3];
  WideRay(const Vec3& o, const Vec3& inv, float tmin_) : org(o), inv_dir(inv), tmin(tmin_) {
    const size_t lo[3] = {offsetof(WideNode, lo_x), offsetof(WideNode, lo_y), offsetof(WideNode, lo_z)};
    const size_t hi[3] = {offsetof(WideNode, hi_x), offsetof(WideNode, hi_y), offsetof(WideNode, hi_z)};
    for (int a = 0; a < 3; ++a) {
      const bool neg = std::signbit(inv[a]);
      near_off[a] = neg ? hi[a] : lo[a];
      far_off[a] = neg ? lo[a] : hi[a];
    }
#if defined(__AVX2__)
    ox = _mm256_set1_ps(o.x); oy = _mm256_set1_ps(o.y); oz = _mm256_set1_ps(o.z);
    ix = _mm256_set1_ps(inv.x); iy = _mm256_set1_ps(inv.y); iz = _mm256_set1_ps(inv.z);
    tmin8 = _mm256_set1_ps(tmin_);
#endif
  }
};

/// Tests the used slots of node against [tmin, tmax]; returns a bit mask of the hit slots and
/// writes every slot's entry distance to dist. The same float operations in the same order
/// as intersect_box_robust, lane by lane, so the result is identical to the scalar test.
/// Unused slots hold empty boxes (lo = +inf, hi = -inf): with sign-selected planes their
/// entry is +inf and exit -inf, so a ray with finite origin and inverse direction never hits
/// them (intersect_children_finite relies on it); this test takes any ray and masks them by
/// node.count.
inline uint32_t intersect_children(const WideNode& node, const WideRay& r, float tmax, float* dist) {
#if defined(__AVX2__)
  const char* base = reinterpret_cast<const char*>(&node);
  const __m256 k = _mm256_set1_ps(kRobustScale), k_neg = _mm256_set1_ps(kRobustScaleNegative);
  __m256 tnear = r.tmin8, tfar = _mm256_set1_ps(tmax);
  auto axis = [&](int a, __m256 o, __m256 inv) {
    const __m256 t0 = plane_distance(_mm256_load_ps(reinterpret_cast<const float*>(base + r.near_off[a])), o, inv);
    __m256 t1 = plane_distance(_mm256_load_ps(reinterpret_cast<const float*>(base + r.far_off[a])), o, inv);
    t1 = _mm256_mul_ps(t1, _mm256_blendv_ps(k, k_neg, t1));  // blendv picks by t1's sign bit
    // max_ps(x, y) = x > y ? x : y and min_ps(x, y) = x < y ? x : y: a NaN first operand
    // keeps the running value, exactly as the scalar ternaries.
    tnear = _mm256_max_ps(t0, tnear);
    tfar = _mm256_min_ps(t1, tfar);
  };
  axis(0, r.ox, r.ix);
  axis(1, r.oy, r.iy);
  axis(2, r.oz, r.iz);
  _mm256_store_ps(dist, tnear);
  // Only used slots: a NaN slab distance (0 * inf, or a NaN direction) keeps the running
  // interval, so an empty slot's infinite planes would pass as well.
  return uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(tnear, tfar, _CMP_LE_OQ))) & ((1u << node.count) - 1u);
#else
  uint32_t mask = 0;
  for (uint32_t c = 0; c < node.count; ++c) {
    float tnear;
    if (intersect_box_robust(r.org, r.inv_dir, node.child_bounds(int(c)), r.tmin, tmax, tnear)) mask |= 1u << c;
    dist[c] = tnear;
  }
  return mask;
#endif
}

// g++ 12 reports a false "__Y may be used uninitialized" inside its own AVX-512 headers.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#if defined(__AVX512F__)
inline constexpr int kNodeGroup = 16;
#else
inline constexpr int kNodeGroup = 8;
#endif

/// Box-tests the nodes ids[0, n) (n <= kNodeGroup) of a Bvh2 against [tmin, tmax] at once;
/// returns the hit mask (bit k = ids[k]) and writes the entry distances to dist[0, kNodeGroup).
/// The same float operations in the same order as intersect_box_robust, lane by lane, so the
/// result is identical to n scalar tests. For the start entries of a seeded traversal: a
/// candidate list holds nodes from anywhere in the tree, of which a ray meets few (about 2 of
/// 12 on Sibenik), and one scalar test per entry, each with its own branch, took a fifth of a
/// seeded ray's time (Sibenik AO rays: 71 ms scalar, 57 ms grouped; docs/history/shafts.md, session 24).
inline uint32_t intersect_nodes(const Bvh2Node* nodes, const uint32_t* ids, int n, const Vec3& org,
                                const Vec3& inv_dir, float tmin, float tmax, float* dist) {
  // A node's record: lo.xyz, hi.xyz, first, count; missing lanes repeat ids[0].
  auto node = [&](int k) { return &nodes[ids[k < n ? k : 0]].bounds.lo.x; };
#if defined(__AVX512F__)
  __m512 f[8];
  transpose_records16(node, f);
  const __m512 lo[3] = {f[0], f[1], f[2]}, hi[3] = {f[3], f[4], f[5]};
  const __m512 k = _mm512_set1_ps(kRobustScale), k_neg = _mm512_set1_ps(kRobustScaleNegative);
  const __m512i sign_bit = _mm512_set1_epi32(INT32_MIN);
  __m512 tnear = _mm512_set1_ps(tmin), tfar = _mm512_set1_ps(tmax);
  for (int a = 0; a < 3; ++a) {
    const bool neg = std::signbit(inv_dir[a]);
    const __m512 o = _mm512_set1_ps(org[a]), inv = _mm512_set1_ps(inv_dir[a]);
    const __m512 t0 = _mm512_mul_ps(_mm512_sub_ps(neg ? hi[a] : lo[a], o), inv);
    __m512 t1 = _mm512_mul_ps(_mm512_sub_ps(neg ? lo[a] : hi[a], o), inv);
    t1 = _mm512_mul_ps(t1, _mm512_mask_blend_ps(_mm512_test_epi32_mask(_mm512_castps_si512(t1), sign_bit), k, k_neg));
    tnear = _mm512_max_ps(t0, tnear);  // NaN t0 keeps tnear, as the scalar ternary
    tfar = _mm512_min_ps(t1, tfar);
  }
  _mm512_storeu_ps(dist, tnear);
  return uint32_t(_mm512_mask_cmp_ps_mask(__mmask16((1u << n) - 1u), tnear, tfar, _CMP_LE_OQ));
#elif defined(__AVX2__)
  // The same with eight nodes.
  __m256 f[8];
  transpose_records8(node, f);
  const __m256 lo[3] = {f[0], f[1], f[2]}, hi[3] = {f[3], f[4], f[5]};
  const __m256 k = _mm256_set1_ps(kRobustScale), k_neg = _mm256_set1_ps(kRobustScaleNegative);
  __m256 tnear = _mm256_set1_ps(tmin), tfar = _mm256_set1_ps(tmax);
  for (int a = 0; a < 3; ++a) {
    const bool neg = std::signbit(inv_dir[a]);
    const __m256 o = _mm256_set1_ps(org[a]), inv = _mm256_set1_ps(inv_dir[a]);
    const __m256 t0 = plane_distance(neg ? hi[a] : lo[a], o, inv);
    __m256 t1 = plane_distance(neg ? lo[a] : hi[a], o, inv);
    t1 = _mm256_mul_ps(t1, _mm256_blendv_ps(k, k_neg, t1));  // blendv picks by t1's sign bit
    tnear = _mm256_max_ps(t0, tnear);
    tfar = _mm256_min_ps(t1, tfar);
  }
  _mm256_storeu_ps(dist, tnear);
  return uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(tnear, tfar, _CMP_LE_OQ))) & ((1u << n) - 1u);
#else
  (void)node;
  uint32_t mask = 0;
  for (int k = 0; k < n; ++k)
    if (intersect_box_robust(org, inv_dir, nodes[ids[k]].bounds, tmin, tmax, dist[k])) mask |= 1u << k;
  return mask;
#endif
}

#pragma GCC diagnostic pop

#if defined(__AVX2__)
/// intersect_children for rays whose origin and inverse direction are finite (no slab
/// distance can be NaN): the same result bit for bit, with a shorter dependency chain.
/// Without NaNs, max and min are associative, so the three axes combine as a tree; and the
/// robust far scale f(t) = t * (t < 0 ? kRobustScaleNegative : kRobustScale) is monotone
/// (rounding is monotone, and f < 0 exactly for t < 0), so min over axes of f(t1) equals
/// f(min over axes of t1): one scale per node instead of one per axis.
inline uint32_t intersect_children_finite(const WideNode& node, const WideRay& r, float tmax, float* dist) {
  const char* base = reinterpret_cast<const char*>(&node);
  auto plane = [&](size_t off) { return _mm256_load_ps(reinterpret_cast<const float*>(base + off)); };
  const __m256 t0x = plane_distance(plane(r.near_off[0]), r.ox, r.ix);
  const __m256 t0y = plane_distance(plane(r.near_off[1]), r.oy, r.iy);
  const __m256 t0z = plane_distance(plane(r.near_off[2]), r.oz, r.iz);
  const __m256 t1x = plane_distance(plane(r.far_off[0]), r.ox, r.ix);
  const __m256 t1y = plane_distance(plane(r.far_off[1]), r.oy, r.iy);
  const __m256 t1z = plane_distance(plane(r.far_off[2]), r.oz, r.iz);
  const __m256 tnear = _mm256_max_ps(_mm256_max_ps(t0x, t0y), _mm256_max_ps(t0z, r.tmin8));
  const __m256 t1 = _mm256_min_ps(_mm256_min_ps(t1x, t1y), t1z);
  const __m256 tfar = _mm256_mul_ps(t1, _mm256_blendv_ps(_mm256_set1_ps(kRobustScale), _mm256_set1_ps(kRobustScaleNegative), t1));
  _mm256_store_ps(dist, tnear);
#if defined(__AVX512F__) && defined(__AVX512VL__)
  return uint32_t(_mm256_cmp_ps_mask(tnear, tfar, _CMP_LE_OQ) & _mm256_cmp_ps_mask(tnear, _mm256_set1_ps(tmax), _CMP_LE_OQ));
#else
  return uint32_t(_mm256_movemask_ps(_mm256_and_ps(_mm256_cmp_ps(tnear, tfar, _CMP_LE_OQ),
                                                   _mm256_cmp_ps(tnear, _mm256_set1_ps(tmax), _CMP_LE_OQ))));
#endif
}
#endif

}  // namespace rayscout::detail
