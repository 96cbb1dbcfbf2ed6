// WideBvh single-ray traversal: SIMD test of 8 child boxes, ordered closest hit, any hit.
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>

#include <immintrin.h>

#include "rayscout/bvh/wide_bvh.h"
#include "rayscout/bvh/cull_interval.h"
#include "traversal_stack.h"
#include "triangle_block_test.h"
#include "box_test.h"

namespace rayscout {
namespace {

struct Entry {
  uint32_t ref;
  float dist;  // entry distance of the ref's box
};

#if defined(__AVX2__)
// A comparator network that sorts lanes by descending key (Lanes = 4: 3 layers on lanes 0..3;
// Lanes = 8: Batcher's 19 comparators in 6 layers), one call of layer(partner, low) per layer:
// partner = each lane's partner lane, low = the lanes (bits) that keep the larger key of their
// pair. Both ISAs below run it; equal keys are never swapped.
template <int Lanes, class Layer>
inline void comparator_network(Layer&& layer) {
  if constexpr (Lanes == 4) {
    layer(_mm256_setr_epi32(1, 0, 3, 2, 4, 5, 6, 7), 0x05u);
    layer(_mm256_setr_epi32(2, 3, 0, 1, 4, 5, 6, 7), 0x03u);
    layer(_mm256_setr_epi32(0, 2, 1, 3, 4, 5, 6, 7), 0x02u);
  } else {
    layer(_mm256_setr_epi32(1, 0, 3, 2, 5, 4, 7, 6), 0x55u);
    layer(_mm256_setr_epi32(2, 3, 0, 1, 6, 7, 4, 5), 0x33u);
    layer(_mm256_setr_epi32(0, 2, 1, 3, 4, 6, 5, 7), 0x22u);
    layer(_mm256_setr_epi32(4, 5, 6, 7, 0, 1, 2, 3), 0x0Fu);
    layer(_mm256_setr_epi32(0, 1, 4, 5, 2, 3, 6, 7), 0x0Cu);
    layer(_mm256_setr_epi32(0, 2, 1, 4, 3, 6, 5, 7), 0x2Au);
  }
}
#endif

#if defined(__AVX512F__) && defined(__AVX512VL__)
// Sorts (key, value) lanes by descending float key. Unused lanes must hold -inf keys.
template <int Lanes>
inline void sort_lanes_descending(__m256& keys, __m256i& vals) {
  comparator_network<Lanes>([&](__m256i partner, unsigned low_bits) {
    const __mmask8 low = __mmask8(low_bits);
    const __m256 pk = _mm256_permutexvar_ps(partner, keys);
    const __m256i pv = _mm256_permutexvar_epi32(partner, vals);
    const __mmask8 swap = (_mm256_cmp_ps_mask(pk, keys, _CMP_GT_OQ) & low) |
                          (_mm256_cmp_ps_mask(pk, keys, _CMP_LT_OQ) & __mmask8(~low));
    keys = _mm256_mask_mov_ps(keys, swap, pk);
    vals = _mm256_mask_mov_epi32(vals, swap, pv);
  });
}
#elif defined(__AVX2__)
// The same with AVX2: integer keys (sortable_key), no mask registers. Unused lanes must hold
// INT32_MIN, below every key.
template <int Lanes>
inline void sort_lanes_descending(__m256i& keys, __m256i& vals) {
  comparator_network<Lanes>([&](__m256i partner, unsigned low_bits) {
    // The bit mask as all-ones lanes (a constant once inlined).
    const __m256i bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    const __m256i low = _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(int(low_bits)), bit), bit);
    const __m256i pk = _mm256_permutevar8x32_epi32(keys, partner);
    const __m256i pv = _mm256_permutevar8x32_epi32(vals, partner);
    const __m256i swap = _mm256_blendv_epi8(_mm256_cmpgt_epi32(keys, pk), _mm256_cmpgt_epi32(pk, keys), low);
    keys = _mm256_blendv_epi8(keys, pk, swap);
    vals = _mm256_blendv_epi8(vals, pv, swap);
  });
}

// Float bits as an int32 with the same order (negative floats: flip the magnitude bits); the
// map is its own inverse. Keeps -inf above the INT32_MIN of unused lanes.
inline __m256i sortable_key(__m256i bits) {
  return _mm256_xor_si256(bits, _mm256_and_si256(_mm256_srai_epi32(bits, 31), _mm256_set1_epi32(INT32_MAX)));
}

// For each 8-bit lane mask, the indices of its set lanes first (3 bits each, lowest first):
// the permutation that compresses those lanes to the front, as AVX-512's compress does.
constexpr std::array<uint32_t, 256> kCompress = [] {
  std::array<uint32_t, 256> t{};
  for (uint32_t m = 0; m < 256; ++m) {
    uint32_t packed = 0;
    int k = 0;
    for (uint32_t l = 0; l < 8; ++l)
      if (m >> l & 1u) packed |= l << (3 * k++);
    t[m] = packed;
  }
  return t;
}();

inline __m256i compress_index(uint32_t mask) {
  return _mm256_and_si256(_mm256_srlv_epi32(_mm256_set1_epi32(int(kCompress[mask])), _mm256_setr_epi32(0, 3, 6, 9, 12, 15, 18, 21)),
                          _mm256_set1_epi32(7));
}
#endif

#if defined(__AVX2__)
// The nearest of the hit children in mask (the lowest slot among equal distances).
inline int nearest_child(uint32_t mask, const float* dist) {
  int near_c = std::countr_zero(mask);
  float near_d = dist[near_c];
  for (mask &= mask - 1; mask; mask &= mask - 1) {
    const int c = std::countr_zero(mask);
    const float d = dist[c];
    near_c = d < near_d ? c : near_c;
    near_d = d < near_d ? d : near_d;
  }
  return near_c;
}

// Pushes the children in rest sorted far to near (the nearest on top) with two 256-bit stores
// (the stack holds kWideWidth entries of slack above its top); returns the new top.
inline Entry* push_far_to_near(Entry* sp, const WideNode& node, const float* dist, uint32_t rest) {
  const int n = std::popcount(rest);
  const __m256i refs = _mm256_load_si256(reinterpret_cast<const __m256i*>(node.child));
#if defined(__AVX512F__) && defined(__AVX512VL__)
  __m256 keys = _mm256_mask_compress_ps(_mm256_set1_ps(-kInfinity), __mmask8(rest), _mm256_load_ps(dist));
  __m256i vals = _mm256_maskz_compress_epi32(__mmask8(rest), refs);
  if (n <= 4) sort_lanes_descending<4>(keys, vals);
  else sort_lanes_descending<8>(keys, vals);
  const __m256i dist_bits = _mm256_castps_si256(keys);
#else
  const __m256i idx = compress_index(rest);
  const __m256i used = _mm256_cmpgt_epi32(_mm256_set1_epi32(n), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
  const __m256i dists = _mm256_permutevar8x32_epi32(_mm256_load_si256(reinterpret_cast<const __m256i*>(dist)), idx);
  __m256i keys = _mm256_blendv_epi8(_mm256_set1_epi32(INT32_MIN), sortable_key(dists), used);
  __m256i vals = _mm256_permutevar8x32_epi32(refs, idx);
  if (n <= 4) sort_lanes_descending<4>(keys, vals);
  else sort_lanes_descending<8>(keys, vals);
  const __m256i dist_bits = sortable_key(keys);
#endif
  // (ref, dist) pairs in lane order.
  const __m256i lo = _mm256_unpacklo_epi32(vals, dist_bits), hi = _mm256_unpackhi_epi32(vals, dist_bits);
  __m256i* top = reinterpret_cast<__m256i*>(sp);
  _mm256_storeu_si256(top, _mm256_permute2x128_si256(lo, hi, 0x20));
  _mm256_storeu_si256(top + 1, _mm256_permute2x128_si256(lo, hi, 0x31));
  return sp + n;
}
#endif

// True when no slab distance of the ray can be NaN: a NaN needs 0 * inf, i.e. an infinite
// inverse direction component, a zero one (an infinite direction) against an empty slot's
// infinite planes, or a non-finite origin or direction.
bool finite_ray(const Ray& ray, const Vec3& inv_dir) {
  return is_finite(inv_dir) && is_finite(ray.org) && is_finite(ray.dir);
}

// The 8 child boxes of a node: the shorter-chain test when the ray is finite (AVX2 only).
template <bool Finite>
inline uint32_t test_children(const WideNode& node, const detail::WideRay& wr, float tmax, float* dist) {
#if defined(__AVX2__)
  if constexpr (Finite) return detail::intersect_children_finite(node, wr, tmax, dist);
#endif
  return detail::intersect_children(node, wr, tmax, dist);
}

}  // namespace

template <bool CaptureStats>
Hit WideBvh::intersect(const Ray& ray, std::span<const uint32_t> start, TraceStats* stats) const {
  return intersect<CaptureStats>(ray, RayPrecomp(ray.dir), start, stats);
}

template <bool CaptureStats>
bool WideBvh::occluded(const Ray& ray, std::span<const uint32_t> start, TraceStats* stats) const {
  return occluded<CaptureStats>(ray, RayPrecomp(ray.dir), start, stats);
}

template <bool CaptureStats>
Hit WideBvh::intersect(const Ray& ray, const RayPrecomp& rp, std::span<const uint32_t> start, TraceStats* stats) const {
  return finite_ray(ray, rp.inv_dir) ? intersect_impl<CaptureStats, true>(ray, rp, start, stats)
                                     : intersect_impl<CaptureStats, false>(ray, rp, start, stats);
}

template <bool CaptureStats>
bool WideBvh::occluded(const Ray& ray, const RayPrecomp& rp, std::span<const uint32_t> start, TraceStats* stats) const {
  return finite_ray(ray, rp.inv_dir) ? occluded_impl<CaptureStats, true>(ray, rp, start, stats)
                                     : occluded_impl<CaptureStats, false>(ray, rp, start, stats);
}

template <bool CaptureStats, bool Finite>
Hit WideBvh::intersect_impl(const Ray& ray, const RayPrecomp& rp, std::span<const uint32_t> start,
                            TraceStats* stats) const {
  Hit best;
  if (nodes.empty()) return best;
  best.t = ray.tmax;
  const CullInterval cull = cull_interval(ray);
  const float box_tmin = cull.near(ray.tmin);
  float cull_t = cull.far(best.t);
  const detail::WideRay wr(ray.org, rp.inv_dir, box_tmin);
  const uint32_t root = 0;
  if (start.empty()) start = std::span<const uint32_t>(&root, 1);
  // + kWideWidth: the sorted push writes a whole group of 8 entries past the top.
  detail::TraversalStack<Entry> stack(start.size() + size_t(depth_) * (kWideWidth - 1) + 2 + kWideWidth);
  uint64_t steps = 0, box_tests = 0, tri_tests = 0;
  // A raw stack pointer: with push/pop on the object its size member stayed in memory
  // (a load and store per push, measured 1-3 % on diffuse, up to 8 % on shadow rays).
  Entry* const stack_base = stack.top();
  Entry* sp = stack_base;
  for (size_t k = start.size(); k-- > 0;) *sp++ = {start[k], box_tmin};
  alignas(32) float dist[kWideWidth];
  const detail::BlockRay<detail::BlockTestLanes> br(ray.org, rp);
  detail::BlockHits bh;
  while (sp != stack_base) {
    Entry e = *--sp;
    // Closed, like the box test. A box entered at the best t (it may hold an equal-t hit
    // with a smaller id) passes either way: cull_t lies CullInterval::far's slack beyond it.
    if (e.dist > cull_t) continue;
    for (;;) {
      ++steps;
      if (WideRef::is_leaf(e.ref)) {
        const uint32_t first = WideRef::leaf_first(e.ref), count = WideRef::leaf_count(e.ref);
        tri_tests += count;
        for (uint32_t slot = first, end = first + count; slot < end;) {
          const uint32_t block = slot / kTriangleBlockWidth, lane0 = slot % kTriangleBlockWidth;
          // Up to two blocks per test: lanes >= 4 (block + 1) are set only when the leaf reaches it.
          const uint32_t n = std::min(detail::kBlockTestLanes - lane0, end - slot);
          const uint32_t slot0 = block * kTriangleBlockWidth;
          detail::intersect_block(&leaf_blocks[block], ((1u << n) - 1u) << lane0, br, ray.tmin, best.t, bh);
          slot += n;
          // Lanes in slot order, each against the running best: the scalar loop's result.
          for (uint32_t m = bh.hit | bh.fallback; m; m &= m - 1) {
            const int l = std::countr_zero(m);
            const uint32_t id = prim_ids[slot0 + l];
            float t, u, v;
            if (bh.fallback >> l & 1u) {
              if (!intersect_triangle(ray.org, rp, leaf_triangle(slot0 + l), ray.tmin, best.t, t, u, v)) continue;
            } else {
              t = bh.t[l];
              u = bh.ev[l] / bh.det[l];
              v = bh.ew[l] / bh.det[l];
            }
            if (is_closer(t, id, best.t, best.prim)) {
              best = {t, id, u, v};
              cull_t = cull.far(t);
            }
          }
        }
        break;
      }
      const WideNode& node = nodes[e.ref];
      // The child references sit on the node's last cache line, read only after the box test:
      // ask for it now, so that read does not add a miss to the chain.
      _mm_prefetch(reinterpret_cast<const char*>(node.child), _MM_HINT_T0);
      box_tests += node.count;
      uint32_t mask = test_children<Finite>(node, wr, cull_t, dist);
      if (mask == 0) break;
      if ((mask & (mask - 1)) == 0) {  // one child: no stack traffic
        const int c = std::countr_zero(mask);
        e = {node.child[c], dist[c]};
        continue;
      }
      const int c0 = std::countr_zero(mask);
      mask &= mask - 1;
      if ((mask & (mask - 1)) == 0) {  // two children: the farther one waits on the stack
        const int c1 = std::countr_zero(mask);
        const Entry a{node.child[c0], dist[c0]}, b{node.child[c1], dist[c1]};
        const bool b_first = b.dist < a.dist;
        *sp++ = b_first ? a : b;
        e = b_first ? b : a;
        continue;
      }
      mask |= 1u << c0;
#if defined(__AVX2__)
      {
        // Three or more: the nearest child by a scalar scan (it is visited next, so this is
        // the critical path); the others sorted far to near by a comparator network, off
        // that path, and pushed at once. Sorting all of them and taking the nearest from the
        // network measured slower than the scalar insertion sort that this replaced, and that
        // the portable branch below still uses (the network's latency is on the path).
        const int near_c = nearest_child(mask, dist);
        sp = push_far_to_near(sp, node, dist, mask & ~(1u << near_c));
        e = {node.child[near_c], dist[near_c]};
        continue;
      }
#else
      // Several: sort far to near (insertion sort, stable), push all but the nearest.
      Entry hits[kWideWidth];
      int n = 0;
      while (mask) {
        const int c = std::countr_zero(mask);
        mask &= mask - 1;
        Entry h{node.child[c], dist[c]};
        int j = n++;
        while (j > 0 && hits[j - 1].dist < h.dist) { hits[j] = hits[j - 1]; --j; }
        hits[j] = h;
      }
      for (int j = 0; j < n - 1; ++j) *sp++ = hits[j];
      e = hits[n - 1];
#endif
    }
  }
  if constexpr (CaptureStats) {
    stats->traversal_steps += steps;
    stats->ray_box_tests += box_tests;
    stats->ray_tri_tests += tri_tests;
  }
  if (!best.hit()) best = Hit{};
  return best;
}

template <bool CaptureStats, bool Finite>
bool WideBvh::occluded_impl(const Ray& ray, const RayPrecomp& rp, std::span<const uint32_t> start,
                            TraceStats* stats) const {
  if (nodes.empty()) return false;
  const CullInterval cull = cull_interval(ray);
  const float box_tmax = cull.far(ray.tmax);
  const detail::WideRay wr(ray.org, rp.inv_dir, cull.near(ray.tmin));
  const uint32_t root = 0;
  if (start.empty()) start = std::span<const uint32_t>(&root, 1);
  detail::TraversalStack<uint32_t> stack(start.size() + size_t(depth_) * (kWideWidth - 1) + 2);
  uint64_t steps = 0, box_tests = 0, tri_tests = 0;
  uint32_t* const stack_base = stack.top();  // raw pointer, as in intersect_impl
  uint32_t* sp = stack_base;
  for (size_t k = start.size(); k-- > 0;) *sp++ = start[k];
  alignas(32) float dist[kWideWidth];
  const detail::BlockRay<detail::Lanes4> br(ray.org, rp);
  detail::BlockHits bh;
  bool hit = false;
  while (sp != stack_base && !hit) {
    uint32_t ref = *--sp;
    for (;;) {
      ++steps;
      if (WideRef::is_leaf(ref)) {
        const uint32_t first = WideRef::leaf_first(ref), count = WideRef::leaf_count(ref);
        for (uint32_t slot = first, end = first + count; slot < end && !hit;) {
          const uint32_t block = slot / kTriangleBlockWidth, lane0 = slot % kTriangleBlockWidth;
          // One block at a time (not two as in intersect_impl): an early hit skips the rest.
          const uint32_t n = std::min(kTriangleBlockWidth - lane0, end - slot);
          const uint32_t lanes = ((1u << n) - 1u) << lane0;
          detail::intersect_lanes<detail::Lanes4>(&leaf_blocks[block], lanes, br, ray.tmin, ray.tmax, bh);
          slot += n;
          tri_tests += n;  // every valid lane was tested
          hit = bh.hit != 0;
          for (uint32_t m = bh.fallback; m && !hit; m &= m - 1) {
            float t, u, v;
            const Triangle tri = leaf_triangle(block * kTriangleBlockWidth + std::countr_zero(m));
            hit = intersect_triangle(ray.org, rp, tri, ray.tmin, ray.tmax, t, u, v);
          }
        }
        break;
      }
      const WideNode& node = nodes[ref];
      box_tests += node.count;
      uint32_t mask = test_children<Finite>(node, wr, box_tmax, dist);
      if (mask == 0) break;
      // Unordered, lowest slot first (sorting by distance measured slower for shadow and AO
      // rays on Sponza): the lowest hit slot is visited next without a stack round trip, the
      // others are pushed last slot first, so the next lowest is on top.
      const int first_c = std::countr_zero(mask);
      for (mask &= mask - 1; mask;) {
        const int c = 31 - std::countl_zero(mask);
        mask &= ~(1u << c);
        *sp++ = node.child[c];
      }
      ref = node.child[first_c];
    }
  }
  if constexpr (CaptureStats) {
    stats->traversal_steps += steps;
    stats->ray_box_tests += box_tests;
    stats->ray_tri_tests += tri_tests;
  }
  return hit;
}

template Hit WideBvh::intersect<false>(const Ray&, std::span<const uint32_t>, TraceStats*) const;
template Hit WideBvh::intersect<true>(const Ray&, std::span<const uint32_t>, TraceStats*) const;
template bool WideBvh::occluded<false>(const Ray&, std::span<const uint32_t>, TraceStats*) const;
template bool WideBvh::occluded<true>(const Ray&, std::span<const uint32_t>, TraceStats*) const;
template Hit WideBvh::intersect<false>(const Ray&, const RayPrecomp&, std::span<const uint32_t>, TraceStats*) const;
template Hit WideBvh::intersect<true>(const Ray&, const RayPrecomp&, std::span<const uint32_t>, TraceStats*) const;
template bool WideBvh::occluded<false>(const Ray&, const RayPrecomp&, std::span<const uint32_t>, TraceStats*) const;
template bool WideBvh::occluded<true>(const Ray&, const RayPrecomp&, std::span<const uint32_t>, TraceStats*) const;

}  // namespace rayscout
