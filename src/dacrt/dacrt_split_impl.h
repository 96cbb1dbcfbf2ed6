// DacrtTracer's triangle split: binned SAH (eq. 1) or sampled cost (eq. 2) over K - 1
// candidates, the midpoint split when |R|/|T| is small, and the ray sampling of Algorithm 2.
#pragma once

#include <immintrin.h>

#include <algorithm>
#include <cmath>

#include "dacrt_tracer.h"

namespace rayscout::dacrt {

template <bool kStats, bool kOccluded>
bool DacrtTracer<kStats, kOccluded>::split(const uint32_t* rid, size_t nr, uint32_t* tid, size_t nt,
                                           const Bounds3& cb, bool sample, Split& s) {
  const int axis = s.axis = cb.largest_axis();
  const float lo = cb.lo[axis], extent = cb.hi[axis] - lo;
  bool separated = false;
  if (extent > 0.0f && std::isfinite(extent)) {
    if (double(nr) <= cfg_.midpoint_ratio * double(nt)) {
      // Few rays per triangle: a cheap midpoint split (sec. 5), sampling only orders and skips.
      const float mid = lo + 0.5f * extent;
      const TriBox* tb = ctx_.tri_boxes;
      s.n_left = size_t(std::partition(tid, tid + nt, [&](uint32_t p) { return tb[p].center(axis) < mid; }) - tid);
      separated = s.n_left > 0 && s.n_left < nt;
      if (separated) bound_sides(tid, nt, s);
    } else {
      separated = binned_split(rid, nr, tid, nt, axis, lo, extent, sample, s);
    }
  }
  if (!separated) {
    if (nt < 2) return false;
    // Centroids (nearly) equal on every axis: halve by position, which still shrinks |T|.
    s.n_left = nt / 2;
    bound_sides(tid, nt, s);
  }
  // Sample rays for the order and skipping only when one of them is on (not for a cost-only run).
  if (sample && !s.sampled && (cfg_.sampled_order || cfg_.skip_partitioning)) sample_split_children(rid, nr, s);
  return true;
}

template <bool kStats, bool kOccluded>
bool DacrtTracer<kStats, kOccluded>::binned_split(const uint32_t* rid, size_t nr, uint32_t* tid, size_t nt,
                                                  int axis, float lo, float extent, bool sample, Split& s) {
  const int k = cfg_.bins;
  bin_triangles(tid, nt, axis, lo, float(k) / extent, k);  // Algorithm 1, line 5
  sweep_bins(k);
  // The sampled cost only where its 2 (K - 1) N_s tests fit the budget (DacrtConfig).
  const bool sampled_cost = sample && cfg_.sampled_cost &&
                            (cfg_.sample_budget <= 0.0 ||
                             double(cfg_.sample_count(nr)) * double(k - 1) <= cfg_.sample_budget * double(nr));
  const size_t ns = sampled_cost ? sample_candidates(rid, nr, axis, k) : 0;
  const int jmin = cheapest_candidate(k, ns);  // Algorithm 1, lines 10-17
  if (jmin < 0) return false;
  s.n_left = partition_by_bin(tid, nt, jmin);
  s.box[0] = left_[jmin].box; s.cb[0] = left_[jmin].cb;
  s.box[1] = right_[jmin].box; s.cb[1] = right_[jmin].cb;
  if (ns > 0) {
    s.sampled = true;
    s.alpha[0] = hit_ratio(c_l_[jmin], ns);
    s.alpha[1] = hit_ratio(c_r_[jmin], ns);
    s.votes[0] = votes_l_[jmin];
    s.votes[1] = votes_r_[jmin];
  }
  return true;
}

template <bool kStats, bool kOccluded>
void DacrtTracer<kStats, kOccluded>::bin_triangles(const uint32_t* tid, size_t nt, int axis, float lo, float scale,
                                                   int k) {
  // Two bin sets, even and odd triangles, so consecutive triangles of one bin do not wait
  // for each other's stores; each triangle's bin is kept for partition_by_bin.
  for (int set = 0; set < 2; ++set)
    for (int j = 0; j < k; ++j) { vbins_[set][j] = VBin::empty(); counts_[set][j] = 0; }
  const TriBox* tb = ctx_.tri_boxes;
  uint8_t* bin_idx = bin_idx_;
  auto add = [&](int set, size_t i) {
    if (i + 16 < nt) _mm_prefetch(reinterpret_cast<const char*>(tb + tid[i + 16]), _MM_HINT_T0);
    const TriBox& t = tb[tid[i]];
    const int b = std::clamp(int((t.center(axis) - lo) * scale), 0, k - 1);
    bin_idx[i] = uint8_t(b);
    vbins_[set][b].extend(t);
    ++counts_[set][b];
  };
  size_t i = 0;
  for (; i + 2 <= nt; i += 2) { add(0, i); add(1, i + 1); }
  if (i < nt) add(0, i);
  for (int j = 0; j < k; ++j) {
    vbins_[0][j].extend(vbins_[1][j]);
    counts_[0][j] += counts_[1][j];
  }
}

template <bool kStats, bool kOccluded>
void DacrtTracer<kStats, kOccluded>::sweep_bins(int k) {
  // left_[j] = bins 0..j, right_[j] = bins j+1..k-1 (candidate j, 0 <= j < k - 1).
  const VBin* bins = vbins_[0];
  VBin acc = VBin::empty();
  uint32_t n_acc = 0;
  auto sweep = [&](int j, Bin& out) {
    acc.extend(bins[j]);
    n_acc += counts_[0][j];
    out.box = acc.box(); out.cb = acc.centroid_bounds(); out.n = n_acc;
  };
  for (int j = 0; j < k - 1; ++j) sweep(j, left_[j]);
  acc = VBin::empty();
  n_acc = 0;
  for (int j = k - 1; j > 0; --j) sweep(j, right_[j - 1]);
}

template <bool kStats, bool kOccluded>
size_t DacrtTracer<kStats, kOccluded>::sample_candidates(const uint32_t* rid, size_t nr, int axis, int k) {
  // Algorithm 1, lines 6-9 (Algorithm 2 for every sample ray and candidate): hit counts
  // c_L, c_R and votes n_L, n_R.
  // Padded as partitioning pads them, so alpha is the share of rays partitioning would keep.
  for (int j = 0; j < k - 1; ++j) { lb_.set(j, padded(left_[j].box, ctx_.pad)); rb_.set(j, padded(right_[j].box, ctx_.pad)); }
  lb_.resize(k - 1); rb_.resize(k - 1);
  const size_t ns = cfg_.sample_count(nr);
  const int padded_count = lb_.count;
  std::fill_n(c_l_, padded_count, 0u); std::fill_n(c_r_, padded_count, 0u);
  std::fill_n(votes_l_, padded_count, 0u); std::fill_n(votes_r_, padded_count, 0u);
  for (size_t q = 0; q < ns; ++q) {
    const RayRecord& r = ctx_.rays[rid[sample_index(q, ns, nr)]];
    sample_pairs(r, lb_, rb_, r.goes_up(axis), cfg_.votes, c_l_, c_r_, votes_l_, votes_r_);
  }
  count_sampling(uint64_t(ns) * 2 * uint64_t(k - 1), true);
  return ns;
}

template <bool kStats, bool kOccluded>
int DacrtTracer<kStats, kOccluded>::cheapest_candidate(int k, size_t ns) const {
  const float area = merge(left_[0].box, right_[0].box).surface_area();
  double best = kInfinity;
  int jmin = -1;
  for (int j = 0; j < k - 1; ++j) {
    const Bin& l = left_[j];
    const Bin& r = right_[j];
    if (l.n == 0 || r.n == 0) continue;
    double pl, pr;
    if (ns > 0) {  // eq. (2)
      pl = hit_ratio(c_l_[j], ns);
      pr = hit_ratio(c_r_[j], ns);
    } else {  // eq. (1), surface-area ratios
      pl = area > 0 ? l.box.surface_area() / area : 1.0;
      pr = area > 0 ? r.box.surface_area() / area : 1.0;
    }
    // Eqs. (1), (2) without C_T + C_I·(...): only the argmin over the bins is used.
    const double cost = pl * l.n + pr * r.n;
    if (cost <= best) { best = cost; jmin = j; }  // Algorithm 1, line 14: <=
  }
  return jmin;
}

template <bool kStats, bool kOccluded>
size_t DacrtTracer<kStats, kOccluded>::partition_by_bin(uint32_t* tid, size_t nt, int jmin) const {
  // std::partition's scheme on the kept bins: a position, once passed, is not read again.
  const uint8_t* bin_idx = bin_idx_;
  size_t a = 0, e = nt;
  for (;;) {
    while (a < e && bin_idx[a] <= jmin) ++a;
    while (a < e && bin_idx[e - 1] > jmin) --e;
    if (a >= e) break;
    std::swap(tid[a], tid[e - 1]);
    ++a; --e;
  }
  return a;
}

template <bool kStats, bool kOccluded>
void DacrtTracer<kStats, kOccluded>::bound_sides(const uint32_t* tid, size_t nt, Split& s) const {
  for (int c = 0; c < 2; ++c) {
    VBin side = VBin::empty();
    for (size_t i = c == 0 ? 0 : s.n_left, end = c == 0 ? s.n_left : nt; i < end; ++i) {
      if (i + 16 < end) _mm_prefetch(reinterpret_cast<const char*>(ctx_.tri_boxes + tid[i + 16]), _MM_HINT_T0);
      side.extend(ctx_.tri_boxes[tid[i]]);
    }
    s.box[c] = side.box();
    s.cb[c] = side.centroid_bounds();
  }
}

template <bool kStats, bool kOccluded>
void DacrtTracer<kStats, kOccluded>::sample_split_children(const uint32_t* rid, size_t nr, Split& s) {
  const size_t ns = cfg_.sample_count(nr);
  uint32_t hits[2];
  const Bounds3 box[2] = {padded(s.box[0], ctx_.pad), padded(s.box[1], ctx_.pad)};
  sample_children(ctx_.rays, ns, [&](size_t q) { return rid[sample_index(q, ns, nr)]; }, box, s.axis, cfg_.votes,
                  hits, s.votes);
  s.alpha[0] = hit_ratio(hits[0], ns);
  s.alpha[1] = hit_ratio(hits[1], ns);
  s.sampled = true;
  count_sampling(2 * ns, true);
}

}  // namespace rayscout::dacrt
