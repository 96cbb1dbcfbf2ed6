// DacrtTracer: the recursion of Algorithm 1 over one contiguous ray range (one task).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include <immintrin.h>

#include "box_kernels.h"
#include "leaf_avx2.h"
#include "leaf_avx512.h"
#include "leaf_kernels.h"
#include "rayscout/core/trace_stats.h"
#include "rayscout/dacrt/dacrt.h"
#include "ray_record.h"

namespace rayscout::dacrt {

/// Read-only per-call data shared by every task, plus the outputs (disjoint per task).
struct TraceContext {
  const DacrtConfig* config;
  RayRecord* rays;            ///< per ray id
  const RayShear* pre;        ///< per ray id, watertight-test constants
  const Triangle* tris;       ///< per triangle id
  const TriBox* tri_boxes;    ///< per triangle id, its bounding box (centre = binning key)
  HitOut hits;                ///< closest-hit outputs (intersect)
  uint8_t* occ;               ///< any-hit outputs (occluded)
  float pad;                  ///< world-space box padding of filtering, pad_for(max coordinate)
};

/// Bounds3 of two SIMD rows (x, y, z, unused).
inline Bounds3 to_bounds(__m128 lo, __m128 hi) {
  alignas(16) float l[4], h[4];
  _mm_store_ps(l, lo);
  _mm_store_ps(h, hi);
  return {Vec3(l[0], l[1], l[2]), Vec3(h[0], h[1], h[2])};
}

/// The box and centroid bounds of a set of triangles as SIMD rows (x, y, z, unused), grown
/// one TriBox at a time: the bins of the binned split and the two sides of a split.
/// min(x, acc) / max(x, acc) are std::min(acc, x) / std::max(acc, x) of Bounds3::extend.
struct VBin {
  __m128 lo, hi, clo, chi;
  static VBin empty() {
    const __m128 pinf = _mm_set1_ps(kInfinity), ninf = _mm_set1_ps(-kInfinity);
    return {pinf, ninf, pinf, ninf};
  }
  void extend(__m128 blo, __m128 bhi, __m128 c) {
    lo = _mm_min_ps(blo, lo); hi = _mm_max_ps(bhi, hi);
    clo = _mm_min_ps(c, clo); chi = _mm_max_ps(c, chi);
  }
  /// Adds a triangle's box and its centre (Bounds3::center()).
  void extend(const TriBox& t) {
    const __m128 blo = _mm_load_ps(t.lo), bhi = _mm_load_ps(t.hi);
    extend(blo, bhi, _mm_mul_ps(_mm_add_ps(blo, bhi), _mm_set1_ps(0.5f)));
  }
  void extend(const VBin& o) {
    lo = _mm_min_ps(o.lo, lo); hi = _mm_max_ps(o.hi, hi);
    clo = _mm_min_ps(o.clo, clo); chi = _mm_max_ps(o.chi, chi);
  }
  Bounds3 box() const { return to_bounds(lo, hi); }
  Bounds3 centroid_bounds() const { return to_bounds(clo, chi); }
};

/// One triangle split: tid[0, n_left) left, the rest right.
struct Split {
  size_t n_left = 0;
  Bounds3 box[2], cb[2];   ///< BV and centroid bounds of left (0) and right (1)
  int axis = 0;
  bool sampled = false;    ///< alpha and votes below come from sample rays
  double alpha[2] = {1, 1};
  uint32_t votes[2] = {0, 0};  ///< n_L, n_R of Algorithm 2
};

/// Recursion over one task's rays; kStats counts work, kOccluded traces any-hit rays.
template <bool kStats, bool kOccluded>
class DacrtTracer {
 public:
  /// scratch: >= |R| ray ids of this task; bin_idx: >= |T| bytes.
  DacrtTracer(const TraceContext& ctx, uint32_t* scratch, uint8_t* bin_idx, uint64_t seed)
      : ctx_(ctx), cfg_(*ctx.config), scratch_(scratch), bin_idx_(bin_idx), rng_(seed | 1) {}

  /// Traces rays rid[0, nr) against triangles tid[0, nt) of the given box and centroid bounds.
  void run(uint32_t* rid, size_t nr, uint32_t* tid, size_t nt, const Bounds3& box, const Bounds3& cb) {
    if (nt == 0 || nr == 0) return;
    const size_t h = partition(rid, nr, box);
    node(rid, h, tid, nt, cb);
  }

  TraceStats stats;
  DacrtStats dacrt_stats;

 private:
  // leaf_next: the rays that hit box go to a leaf next, so their shear records are prefetched.
  size_t partition(uint32_t* rid, size_t nr, const Bounds3& box, bool leaf_next = false) {
    if constexpr (kStats) { stats.ray_box_tests += nr; dacrt_stats.partition_box_tests += nr; }
    return partition_rays(ctx_.rays, rid, nr, padded(box, ctx_.pad), scratch_, leaf_next ? ctx_.pre : nullptr);
  }

  void leaf(const uint32_t* rid, size_t nr, const uint32_t* tid, size_t nt) {
    const uint64_t tests = leaf_tests(rid, nr, tid, nt);
    if constexpr (kStats) { stats.ray_tri_tests += tests; ++dacrt_stats.leaves; }
  }

  uint64_t leaf_tests(const uint32_t* rid, size_t nr, const uint32_t* tid, size_t nt) {
#if defined(__AVX512F__) || defined(__AVX2__)
    if (nr >= 8)  // 16 (AVX-512) or 8 (AVX2) rays per triangle test
      return leaf_simd<kOccluded>(ctx_.rays, ctx_.pre, rid, nr, ctx_.tris, tid, nt, ctx_.hits, ctx_.occ);
#endif
#if defined(__AVX512F__)
    if (nt >= 8)  // a handful of rays: 16 triangles per ray test
      return leaf_few_rays<kOccluded>(ctx_.rays, ctx_.pre, rid, nr, ctx_.tris, tid, nt, ctx_.hits, ctx_.occ);
#endif
    if constexpr (kOccluded) return leaf_occluded(ctx_.rays, ctx_.pre, rid, nr, ctx_.tris, tid, nt, ctx_.occ);
    else return leaf_intersect(ctx_.rays, ctx_.pre, rid, nr, ctx_.tris, tid, nt, ctx_.hits);
  }

  // Algorithm 1, DACRT(R, T, cb). rid[0, nr) all hit this node's box (or were passed on
  // unfiltered); tid[0, nt) are the node's triangles, cb the bounds of their box centres.
  void node(uint32_t* rid, size_t nr, uint32_t* tid, size_t nt, const Bounds3& cb) {
    if constexpr (kStats) ++stats.traversal_steps;
    if (nr == 0) return;
    if (nr < cfg_.delta_r || nt < cfg_.delta_t) { leaf(rid, nr, tid, nt); return; }  // lines 2-4
    Split s;  // lines 5-17
    const bool sample = cfg_.samples_rays() && nr >= cfg_.min_rays_sampling;
    if (!split(rid, nr, tid, nt, cb, sample, s)) { leaf(rid, nr, tid, nt); return; }

    const int first = first_child(rid, nt, s);
    // Lines 25-34: each child in order, its rays filtered against its box (with the hit
    // distances the first child left) or, when sampling says most would hit it, passed on
    // unfiltered (eq. 5 in place of line 25's threshold, see DacrtConfig::skip_threshold).
    for (int k = 0; k < 2; ++k) {
      const int c = k == 0 ? first : 1 - first;
      uint32_t* ctid = c == 0 ? tid : tid + s.n_left;
      const size_t cnt = c == 0 ? s.n_left : nt - s.n_left;
      // alpha of the second child: the share of R that hits its box with the hit distances
      // left by the first child, which is what partitioning would test (eqs. 3-5).
      if (k == 1 && s.sampled && cfg_.skip_partitioning && cfg_.resample_second) s.alpha[c] = resampled_alpha(rid, nr, s.box[c]);
      if (s.sampled && cfg_.skip_partitioning && s.alpha[c] > cfg_.skip_threshold(cnt)) {
        if constexpr (kStats) ++dacrt_stats.skipped_partitions;
        node(rid, nr, ctid, cnt, s.cb[c]);
      } else {
        const size_t h = partition(rid, nr, s.box[c], cnt < cfg_.delta_t);
        node(rid, h, ctid, cnt, s.cb[c]);
      }
    }
  }

  // Lines 18-24: the child visited first, 0 (left) or 1 (right).
  int first_child(const uint32_t* rid, size_t nt, const Split& s) const {
    if (s.sampled && cfg_.sampled_order && s.votes[0] + s.votes[1] > 0)  // line 18, weighed by depth in dacrt-rs
      return first_child_by_votes(s.votes[0], s.votes[1], s.n_left, nt - s.n_left, cfg_.depth_weighted_votes);
    // Afra: one ray (the first of the set) decides, by its direction along the split axis.
    return ctx_.rays[rid[0]].goes_up(s.axis) ? 0 : 1;
  }

  // alpha of box measured again: the share of N_s sample rays of rid[0, nr) hitting it with
  // their current hit distance (DacrtConfig::resample_second).
  double resampled_alpha(const uint32_t* rid, size_t nr, const Bounds3& box) {
    const size_t ns = cfg_.sample_count(nr);
    const Bounds3 filter_box = padded(box, ctx_.pad);
    uint32_t hits = 0;
    for (size_t q = 0; q < ns; ++q) {
      float tnear;
      hits += ray_hits_box(ctx_.rays[rid[sample_index(q, ns, nr)]], filter_box, tnear);
    }
    count_sampling(ns, false);
    return hit_ratio(hits, ns);
  }

  // alpha = c / N_s, the share of the sample rays that hit a box (Algorithm 1, line 12).
  static double hit_ratio(uint32_t hits, size_t ns) { return double(hits) / double(ns); }

  // Counts `tests` ray-box tests of sample rays; new_node: the node draws its sample rays.
  void count_sampling(uint64_t tests, bool new_node) {
    if constexpr (kStats) {
      stats.ray_box_tests += tests;
      dacrt_stats.sampling_box_tests += tests;
      dacrt_stats.sampled_nodes += new_node;
    }
  }

  // Chooses and performs the triangle split; false when the triangles cannot be separated.
  __attribute__((noinline)) bool split(const uint32_t* rid, size_t nr, uint32_t* tid, size_t nt,
                                       const Bounds3& cb, bool sample, Split& s);
  // The binned split (K bins over the centroid bounds): eq. (2) over sampled candidates when
  // sampled, else eq. (1); false when no candidate separates the triangles.
  bool binned_split(const uint32_t* rid, size_t nr, uint32_t* tid, size_t nt, int axis, float lo, float extent,
                    bool sample, Split& s);
  // Bins tid[0, nt) by centroid into vbins_[0], counts_[0] and bin_idx_.
  void bin_triangles(const uint32_t* tid, size_t nt, int axis, float lo, float scale, int k);
  // The candidates' left_ and right_ bins from the binned triangles.
  void sweep_bins(int k);
  // Algorithm 2 over the K - 1 candidates; returns the number of sample rays N_s.
  size_t sample_candidates(const uint32_t* rid, size_t nr, int axis, int k);
  // The candidate of least cost (eq. (2) when ns > 0, else eq. (1)); -1 when none separates.
  int cheapest_candidate(int k, size_t ns) const;
  // Moves the triangles of bins 0..jmin to the front; returns their count.
  size_t partition_by_bin(uint32_t* tid, size_t nt, int jmin) const;
  // Algorithm 2 against the two children of a split already chosen (midpoint, or SAH over
  // the sampling budget): fills s.alpha and s.votes for the order and skipping.
  __attribute__((noinline)) void sample_split_children(const uint32_t* rid, size_t nr, Split& s);
  // Position in rid[0, nr) of sample ray q of ns: a fixed stride (sec. 4.1) or, with the
  // random strategy, the next draw of the task's xorshift generator (fig. 9).
  size_t sample_index(size_t q, size_t ns, size_t nr) {
    if (cfg_.strategy == DacrtSampling::Stride) return q * (nr / ns);
    rng_ ^= rng_ << 13; rng_ ^= rng_ >> 7; rng_ ^= rng_ << 17;  // xorshift64
    return size_t(rng_ % nr);
  }
  // The box and centroid bounds of both sides of s (tid[0, n_left) and the rest).
  void bound_sides(const uint32_t* tid, size_t nt, Split& s) const;

  const TraceContext& ctx_;
  const DacrtConfig& cfg_;
  uint32_t* scratch_;
  uint8_t* bin_idx_;  // bin of each triangle position of the node being split
  uint64_t rng_;
  // Binning and sampling buffers, reused by every node (no per-node allocation).
  struct Bin { Bounds3 box, cb; uint32_t n = 0; };
  Bin left_[256], right_[256];
  VBin vbins_[2][256];
  uint32_t counts_[2][256];
  BoxSoa lb_, rb_;
  // c_L, c_R (sample rays hitting each candidate's boxes) and n_L, n_R (votes) of Algorithm 2.
  alignas(64) uint32_t c_l_[256], c_r_[256], votes_l_[256], votes_r_[256];
};

}  // namespace rayscout::dacrt

#include "dacrt_split_impl.h"
