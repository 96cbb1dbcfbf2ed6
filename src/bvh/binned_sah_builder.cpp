// Binned SAH builder: Wald 2007 binning over centroid bounds, SSE arithmetic, parallel with oneTBB.
#include "binned_sah_builder.h"

#include <immintrin.h>

#include <algorithm>
#include <atomic>
#include <array>
#include <limits>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>

#include "rayscout/core/input_error.h"

namespace rayscout::detail {
namespace {

// A box as two SSE registers (x, y, z, unused); the builder's working format.
struct Box4 {
  __m128 lo = _mm_set1_ps(kInfinity), hi = _mm_set1_ps(-kInfinity);
  void extend(__m128 l, __m128 h) { lo = _mm_min_ps(lo, l); hi = _mm_max_ps(hi, h); }
  void extend(const Box4& b) { extend(b.lo, b.hi); }
  void extend(__m128 p) { extend(p, p); }
  // Half the surface area (the factor 2 cancels in every SAH comparison); 0 when empty.
  float half_area() const {
    alignas(16) float d[4];
    _mm_store_ps(d, _mm_sub_ps(hi, lo));
    if (d[0] < 0.0f || d[1] < 0.0f || d[2] < 0.0f) return 0.0f;
    return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
  }
  Bounds3 bounds() const {
    alignas(16) float l[4], h[4];
    _mm_store_ps(l, lo);
    _mm_store_ps(h, hi);
    return {{l[0], l[1], l[2]}, {h[0], h[1], h[2]}};
  }
};

// Trivially constructible, so only the bins a node uses are ever cleared.
struct Box4Raw {
  __m128 lo, hi;
};

struct Bin {
  Box4Raw box;
  uint32_t count;
  void clear() { box.lo = _mm_set1_ps(kInfinity); box.hi = _mm_set1_ps(-kInfinity); count = 0; }
  // One more primitive of box b.
  void add(const Box4& b) { box.lo = _mm_min_ps(box.lo, b.lo); box.hi = _mm_max_ps(box.hi, b.hi); ++count; }
  // The union with bin o (another task's share of the same node).
  void merge(const Bin& o) {
    box.lo = _mm_min_ps(box.lo, o.box.lo);
    box.hi = _mm_max_ps(box.hi, o.box.hi);
    count += o.count;
  }
};

struct Split {
  int axis = -1;
  int bin = 0;        // left side = bins [0, bin]
  float cost = 0.0f;  // A_L N_L + A_R N_R (half areas)
  int bins = 0;       // bin count used for this node
  Box4 left, right;   // child boxes: unions of their bins
};

// What a subtree needs: its primitives' box and the bounds of their doubled centres.
struct Range {
  uint32_t begin, end;
  Box4 box, cbox;
};

// A primitive as the builder moves it around: its box and id (Embree's PrimRef).
// Partitioning these, rather than ids into a box array, keeps every pass over a node's
// primitives sequential in memory.
struct PrimRef : Box4 {
  uint32_t id = 0;
};

class Builder {
 public:
  Builder(std::span<PrimRef> refs, const BvhBuildConfig& c, std::vector<Bvh2Node>& slots)
      : refs_(refs), config_(c), slots_(slots) {}

  // Builds the subtree of refs_[r.begin, r.end) into slots_[slot]; its descendants go to the
  // 2 n - 2 slots starting at desc (a binary tree over n primitives has <= 2 n - 1 nodes),
  // which makes slot numbering independent of task scheduling.
  void build(uint32_t slot, const Range& r, uint32_t desc) {
    const uint32_t n = r.end - r.begin;
    Bvh2Node& node = slots_[slot];
    node.bounds = r.box.bounds();
    node.pad = 0;
    node.axis = 0;
    if (n == 1) return make_leaf(node, r.begin, n);
    const Split split = find_split(r);
    if (n <= uint32_t(config_.max_leaf_size) && (split.axis < 0 || leaf_costs_no_more(r, split)))
      return make_leaf(node, r.begin, n);
    Range left, right;
    if (split.axis >= 0) {
      partition(r, split, left, right);
      node.axis = uint8_t(split.axis);
    } else {
      // Every centre is equal, or no split has a finite non-zero cost: split the list in half.
      node.axis = uint8_t(median_split(r, left, right));
    }
    const uint32_t nl = left.end - left.begin;
    node.first = desc;
    node.count = 0;
    auto build_left = [&] { build(desc, left, desc + 2); };
    auto build_right = [&] { build(desc + 1, right, desc + 2 * nl); };
    if (n >= uint32_t(config_.parallel_threshold)) {
      tbb::parallel_invoke(build_left, build_right);
    } else {
      build_left();
      build_right();
    }
  }

 private:
  // Intersection tests a side of n primitives costs: leaves test leaf_block triangles at once,
  // so the split SAH counts blocks like the leaf cost does (Embree's "block shift"); with
  // per-triangle counts here, leaves of up to max_leaf_size looked cheaper than any split.
  uint32_t blocks(uint32_t n) const { return (n + uint32_t(config_.leaf_block) - 1) / uint32_t(config_.leaf_block); }

  // The SAH's leaf-or-split decision (Wald 2007 eq. 1) multiplied through by A(box), so flat
  // boxes need no division: C_I blocks(n) A <= C_T A + C_I (A_L N_L + A_R N_R). A tie makes a leaf.
  bool leaf_costs_no_more(const Range& r, const Split& split) const {
    const float area = r.box.half_area();
    const float split_cost = config_.traversal_cost * area + config_.intersection_cost * split.cost;
    const float leaf_cost = config_.intersection_cost * float(blocks(r.end - r.begin)) * area;
    return leaf_cost <= split_cost;
  }

  void make_leaf(Bvh2Node& node, uint32_t begin, uint32_t n) {
    node.first = begin;
    node.count = uint16_t(n);
    leaves_.fetch_add(1, std::memory_order_relaxed);
  }

  // Maps doubled centres to bins: bin = (c2 - lo) * scale per axis, clamped to [0, top].
  struct Binner {
    __m128 lo, scale;
    int top;
    // Bin index per axis (idx[0..2]; idx[3] is scratch) of a doubled centre.
    void index(__m128 c2, int* idx) const {
      _mm_store_si128(reinterpret_cast<__m128i*>(idx), _mm_cvttps_epi32(_mm_mul_ps(_mm_sub_ps(c2, lo), scale)));
      for (int a = 0; a < 3; ++a) idx[a] = std::clamp(idx[a], 0, top);
    }
  };

  Binner binner(const Box4& cbox, int bins) const {
    alignas(16) float lo[4], hi[4], s[4] = {0, 0, 0, 0};
    _mm_store_ps(lo, cbox.lo);
    _mm_store_ps(hi, cbox.hi);
    // The top centre lands inside the last bin: (hi - lo) * scale = bins * kShrink < bins.
    constexpr float kShrink = 1.0f - 1e-6f;
    for (int a = 0; a < 3; ++a) {
      const float e = hi[a] - lo[a];
      s[a] = e > 0.0f ? float(bins) * kShrink / e : 0.0f;
    }
    return {cbox.lo, _mm_load_ps(s), bins - 1};
  }

  template <int NB>
  using BinArray = std::array<std::array<Bin, NB>, 3>;

  template <int NB>
  void bin_range(uint32_t begin, uint32_t end, const Binner& b, BinArray<NB>& bins) const {
    alignas(16) int idx[4];
    for (uint32_t i = begin; i < end; ++i) {
      const Box4& box = refs_[i];
      b.index(_mm_add_ps(box.lo, box.hi), idx);
      for (int a = 0; a < 3; ++a) bins[a][idx[a]].add(box);
    }
  }

  Split find_split(const Range& r) const {
    // Bin storage sized to the configured count: clearing the bins is a real cost per node.
    if (config_.bins <= 16) return find_split_n<16>(r);
    if (config_.bins <= 32) return find_split_n<32>(r);
    if (config_.bins <= 64) return find_split_n<64>(r);
    return find_split_n<kBvhMaxBins>(r);
  }

  template <int NB>
  Split find_split_n(const Range& r) const {
    Split best;
    const Vec3 extent = r.cbox.bounds().diagonal();
    if (!(extent.x > 0.0f || extent.y > 0.0f || extent.z > 0.0f)) return best;
    // Fewer primitives than bins: one bin per primitive (clearing and sweeping unused bins
    // dominates the cost of small nodes).
    const int nb = int(std::min<uint32_t>(uint32_t(config_.bins), std::max<uint32_t>(2u, r.end - r.begin)));
    BinArray<NB> bins;
    bin_primitives<NB>(r, binner(r.cbox, nb), nb, bins);
    for (int a = 0; a < 3; ++a)
      if (extent[a] > 0.0f) sweep_axis<NB>(bins[a], a, nb, best);
    // Boxes without area (collinear input) or with an infinite one cost every split the same,
    // 0 or inf: the first bin would win at every level, peeling one bin off a chain of nodes
    // (depth 2257 for 1M collinear triangles). The median split halves them instead.
    if (!(best.cost > 0.0f && best.cost < std::numeric_limits<float>::infinity())) best.axis = -1;
    if (best.axis >= 0)
      for (int k = 0; k < nb; ++k) {
        const Bin& bin = bins[best.axis][k];
        (k <= best.bin ? best.left : best.right).extend(bin.box.lo, bin.box.hi);
      }
    best.bins = nb;
    return best;
  }

  // Bins r's primitives by centre into the first nb bins of each axis, in parallel for a
  // large node; the other bins are left as they are.
  template <int NB>
  void bin_primitives(const Range& r, const Binner& binr, int nb, BinArray<NB>& bins) const {
    auto clear = [nb](BinArray<NB>& b) {
      for (int ax = 0; ax < 3; ++ax)
        for (int k = 0; k < nb; ++k) b[ax][k].clear();
    };
    if (r.end - r.begin < uint32_t(config_.parallel_threshold)) {
      clear(bins);
      bin_range<NB>(r.begin, r.end, binr, bins);
      return;
    }
    BinArray<NB> empty;
    clear(empty);
    // Bin unions and counts are exact, so the reduction order cannot change the result.
    bins = tbb::parallel_reduce(
        tbb::blocked_range<uint32_t>(r.begin, r.end, 1024), empty,
        [&](const tbb::blocked_range<uint32_t>& br, BinArray<NB> acc) {
          bin_range<NB>(br.begin(), br.end(), binr, acc);
          return acc;
        },
        [nb](BinArray<NB> a, const BinArray<NB>& b) {
          for (int ax = 0; ax < 3; ++ax)
            for (int k = 0; k < nb; ++k) a[ax][k].merge(b[ax][k]);
          return a;
        });
  }

  // The SAH sweep over one axis' nb bins (Wald 2007 sec. 3.2): the split after bin k costs
  // A_L N_L + A_R N_R (half areas, N in leaf blocks); best takes it when it is cheaper than
  // every split before (lower axes first, then lower k: ties keep the first).
  template <int NB>
  void sweep_axis(const std::array<Bin, NB>& bins, int axis, int nb, Split& best) const {
    // From the right: right_cost[k] and right_count[k] are A N and N of bins (k, nb).
    std::array<float, NB> right_cost;
    std::array<uint32_t, NB> right_count;
    Box4 right;
    uint32_t count = 0;
    for (int k = nb - 1; k > 0; --k) {
      right.extend(bins[k].box.lo, bins[k].box.hi);
      count += bins[k].count;
      right_cost[k - 1] = right.half_area() * float(blocks(count));
      right_count[k - 1] = count;
    }
    Box4 left;
    count = 0;
    for (int k = 0; k < nb - 1; ++k) {
      left.extend(bins[k].box.lo, bins[k].box.hi);
      count += bins[k].count;
      if (count == 0 || right_count[k] == 0) continue;
      const float cost = left.half_area() * float(blocks(count)) + right_cost[k];
      if (best.axis < 0 || cost < best.cost) {
        best.axis = axis;
        best.bin = k;
        best.cost = cost;
      }
    }
  }

  // In-place partition by bin (the binning's own arithmetic, so sides match the bins exactly);
  // gathers each side's centre bounds on the way.
  void partition(const Range& r, const Split& s, Range& left, Range& right) const {
    const Binner binr = binner(r.cbox, s.bins);
    alignas(16) int idx[4];
    auto goes_left = [&](const PrimRef& p, __m128& c2) {
      c2 = _mm_add_ps(p.lo, p.hi);
      binr.index(c2, idx);
      return idx[s.axis] <= s.bin;
    };
    PrimRef* refs = refs_.data();
    uint32_t i = r.begin, j = r.end;
    Box4 lc, rc;
    __m128 c2;
    for (;;) {
      while (i < j && goes_left(refs[i], c2)) { lc.extend(c2); ++i; }
      while (i < j && !goes_left(refs[j - 1], c2)) { rc.extend(c2); --j; }
      if (i >= j) break;
      // refs[i] goes right, refs[j - 1] goes left: swap them into place.
      std::swap(refs[i], refs[j - 1]);
      lc.extend(_mm_add_ps(refs[i].lo, refs[i].hi));
      rc.extend(_mm_add_ps(refs[j - 1].lo, refs[j - 1].hi));
      ++i;
      --j;
    }
    left = {r.begin, i, s.left, lc};
    right = {i, r.end, s.right, rc};
  }

  // Halves r at the median centre along the largest axis of its box (equal centres ordered by
  // id, so each half is defined by centres and ids alone); returns that axis.
  int median_split(const Range& r, Range& left, Range& right) const {
    const uint32_t mid = r.begin + (r.end - r.begin) / 2;
    const int axis = r.box.bounds().largest_axis();
    PrimRef* b = refs_.data();
    auto centre = [&](const PrimRef& p) {
      alignas(16) float c[4];
      _mm_store_ps(c, _mm_add_ps(p.lo, p.hi));
      return c[axis];
    };
    std::nth_element(b + r.begin, b + mid, b + r.end, [&](const PrimRef& p, const PrimRef& q) {
      const float cp = centre(p), cq = centre(q);
      return cp < cq || (cp == cq && p.id < q.id);
    });
    left = gather(r.begin, mid);
    right = gather(mid, r.end);
    return axis;
  }

  // The Range of refs_[begin, end): its box and centre bounds, by one pass.
  Range gather(uint32_t begin, uint32_t end) const {
    Range r{begin, end, {}, {}};
    for (uint32_t i = begin; i < end; ++i) {
      const Box4& b = refs_[i];
      r.box.extend(b);
      r.cbox.extend(_mm_add_ps(b.lo, b.hi));
    }
    return r;
  }

  std::span<PrimRef> refs_;
  const BvhBuildConfig& config_;
  std::vector<Bvh2Node>& slots_;
  std::atomic<uint32_t> leaves_{0};

 public:
  /// Leaves made so far: a binary tree with L leaves has 2 L - 1 nodes.
  uint32_t leaf_count() const { return leaves_.load(); }
};

}  // namespace

void check_primitive_count(uint64_t count) {
  if (count >= (uint64_t(1) << 27))
    throw InputError("BVH: " + std::to_string(count) +
                     " primitives (triangles, or their pieces with presplit), at most 2^27 - 1 (134217727) supported");
}

int build_binned_sah(std::span<const Bounds3> boxes, const BvhBuildConfig& config,
                     std::vector<Bvh2Node>& nodes, std::vector<uint32_t>& prim_ids) {
  if (config.bins < 2 || config.bins > kBvhMaxBins)
    throw InputError("BvhBuildConfig.bins = " + std::to_string(config.bins) + ": must be in [2, " +
                     std::to_string(kBvhMaxBins) + "]");
  if (config.max_leaf_size < 1 || config.max_leaf_size > kBvhMaxLeafSize)
    throw InputError("BvhBuildConfig.max_leaf_size = " + std::to_string(config.max_leaf_size) + ": must be in [1, " +
                     std::to_string(kBvhMaxLeafSize) + "]");
  if (config.leaf_block < 1)
    throw InputError("BvhBuildConfig.leaf_block = " + std::to_string(config.leaf_block) + ": must be >= 1");
  check_primitive_count(boxes.size());
  const uint32_t n = uint32_t(boxes.size());
  nodes.clear();
  prim_ids.resize(n);
  if (n == 0) return 0;

  std::vector<PrimRef> refs(n);
  struct Both { Box4 box, cbox; };
  const Both all = tbb::parallel_reduce(
      tbb::blocked_range<uint32_t>(0, n, 4096), Both{},
      [&](const tbb::blocked_range<uint32_t>& r, Both acc) {
        for (uint32_t i = r.begin(); i != r.end(); ++i) {
          const Bounds3& b = boxes[i];
          refs[i].lo = _mm_setr_ps(b.lo.x, b.lo.y, b.lo.z, 0.0f);
          refs[i].hi = _mm_setr_ps(b.hi.x, b.hi.y, b.hi.z, 0.0f);
          acc.box.extend(refs[i]);
          acc.cbox.extend(_mm_add_ps(refs[i].lo, refs[i].hi));
          refs[i].id = i;
        }
        return acc;
      },
      [](Both a, const Both& b) { a.box.extend(b.box); a.cbox.extend(b.cbox); return a; });

  std::vector<Bvh2Node> slots(2 * size_t(n) - 1);
  Builder builder(refs, config, slots);
  builder.build(0, {0, n, all.box, all.cbox}, 1);
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n, 4096), [&](const auto& r) {
    for (uint32_t i = r.begin(); i != r.end(); ++i) prim_ids[i] = refs[i].id;
  });

  // Compact the scheduling-independent slot layout into depth-first order, siblings adjacent.
  // Exactly the reachable nodes: no over-sized buffer to shrink and copy (first touches of
  // fresh pages are a large part of a cold build).
  nodes.reserve(2 * size_t(builder.leaf_count()) - 1);
  nodes.push_back(slots[0]);
  struct Item { uint32_t node, slot; int depth; };
  std::vector<Item> stack{{0, 0, 0}};
  int depth = 0;
  while (!stack.empty()) {
    const Item it = stack.back();
    stack.pop_back();
    depth = std::max(depth, it.depth);
    const Bvh2Node s = slots[it.slot];
    if (s.is_leaf()) continue;
    const uint32_t c = uint32_t(nodes.size());
    nodes.push_back(slots[s.first]);
    nodes.push_back(slots[s.first + 1]);
    nodes[it.node].first = c;
    stack.push_back({c + 1, s.first + 1, it.depth + 1});
    stack.push_back({c, s.first, it.depth + 1});
  }
  return depth;
}

}  // namespace rayscout::detail
