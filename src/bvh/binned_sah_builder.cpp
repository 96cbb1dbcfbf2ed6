// Binned SAH builder: Wald 2007 binning over centroid bounds, parallel with oneTBB.
#include "binned_sah_builder.h"

#include <algorithm>
#include <array>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>

#include "rayscout/core/accelerator_options.h"

namespace rayscout::detail {
namespace {

constexpr int kMaxBins = 256;

struct Bin {
  Bounds3 box;    // union of the primitives' boxes
  Bounds3 cbox;   // union of their centroids
  uint32_t count = 0;
  void add(const Bin& o) { box.extend(o.box); cbox.extend(o.cbox); count += o.count; }
};

struct Split {
  int axis = -1;
  int bin = 0;          // left side = bins [0, bin]
  float cost = 0.0f;    // A_L N_L + A_R N_R
  Bin left, right;
};

class Builder {
 public:
  Builder(std::span<const Bounds3> boxes, std::span<const Vec3> centers, const BvhBuildConfig& c,
          std::vector<Bvh2Node>& slots, std::vector<uint32_t>& ids)
      : boxes_(boxes), centers_(centers), config_(c), slots_(slots), ids_(ids) {}

  // Builds the subtree of ids_[begin, end) into slots_[slot]; its descendants go to the
  // 2 n - 2 slots starting at desc (a binary tree over n leaves-or-more has <= 2 n - 1 nodes),
  // which makes slot numbering independent of task scheduling.
  void build(uint32_t slot, uint32_t begin, uint32_t end, const Bounds3& box, const Bounds3& cbox,
             uint32_t desc) {
    const uint32_t n = end - begin;
    Bvh2Node& node = slots_[slot];
    node.bounds = box;
    node.pad = 0;
    node.axis = 0;
    const bool can_be_leaf = n <= uint32_t(config_.max_leaf_size);
    Split split;
    const Vec3 extent = cbox.diagonal();
    if (n > 1 && (extent.x > 0.0f || extent.y > 0.0f || extent.z > 0.0f)) split = find_split(begin, end, cbox);
    if (n == 1 || (split.axis < 0 && can_be_leaf)) return make_leaf(node, begin, n);
    if (split.axis >= 0 && can_be_leaf) {
      // SAH (Wald 2007 eq. 1) multiplied through by A(box), so flat boxes need no division.
      const float area = box.surface_area();
      const float split_cost = config_.traversal_cost * area + config_.intersection_cost * split.cost;
      const float leaf_cost = config_.intersection_cost * float(n) * area;
      if (leaf_cost <= split_cost) return make_leaf(node, begin, n);
    }
    uint32_t mid;
    Bin left, right;
    if (split.axis >= 0) {
      mid = partition(begin, end, cbox, split.axis, split.bin);
      left = split.left;
      right = split.right;
      node.axis = uint8_t(split.axis);
    } else {
      // Every centroid is equal (or binning found no split): split the list in half.
      const int axis = extent.x > 0 || extent.y > 0 || extent.z > 0 ? max_axis(extent) : box.largest_axis();
      mid = begin + n / 2;
      auto* b = ids_.data();
      std::nth_element(b + begin, b + mid, b + end, [&](uint32_t p, uint32_t q) {
        const float cp = centers_[p][axis], cq = centers_[q][axis];
        return cp < cq || (cp == cq && p < q);
      });
      left = bounds_of(begin, mid);
      right = bounds_of(mid, end);
      node.axis = uint8_t(axis);
    }
    const uint32_t nl = mid - begin;
    node.first = desc;
    node.count = 0;
    auto build_left = [&] { build(desc, begin, mid, left.box, left.cbox, desc + 2); };
    auto build_right = [&] { build(desc + 1, mid, end, right.box, right.cbox, desc + 2 * nl); };
    if (n >= uint32_t(config_.parallel_threshold)) {
      tbb::parallel_invoke(build_left, build_right);
    } else {
      build_left();
      build_right();
    }
  }

 private:
  void make_leaf(Bvh2Node& node, uint32_t begin, uint32_t n) {
    node.first = begin;
    node.count = uint16_t(n);
  }

  // Bin index of a centroid coordinate; the scale keeps the top value inside the last bin.
  static int bin_of(float c, float lo, float scale, int bins) {
    const int b = int((c - lo) * scale);
    return std::clamp(b, 0, bins - 1);
  }

  std::array<float, 3> scales(const Bounds3& cbox) const {
    std::array<float, 3> s{};
    const Vec3 e = cbox.diagonal();
    for (int a = 0; a < 3; ++a) s[a] = e[a] > 0.0f ? float(config_.bins) * (1.0f - 1e-6f) / e[a] : 0.0f;
    return s;
  }

  template <int NB>
  using BinArray = std::array<std::array<Bin, NB>, 3>;

  template <int NB>
  void bin_range(uint32_t begin, uint32_t end, const Bounds3& cbox, const std::array<float, 3>& s,
                 BinArray<NB>& bins) const {
    for (uint32_t i = begin; i < end; ++i) {
      const uint32_t p = ids_[i];
      const Vec3& c = centers_[p];
      for (int a = 0; a < 3; ++a) {
        if (s[a] == 0.0f) continue;
        Bin& b = bins[a][bin_of(c[a], cbox.lo[a], s[a], config_.bins)];
        b.box.extend(boxes_[p]);
        b.cbox.extend(c);
        ++b.count;
      }
    }
  }

  Split find_split(uint32_t begin, uint32_t end, const Bounds3& cbox) const {
    // Bin storage sized to the configured count: clearing the bins is a real cost per node.
    if (config_.bins <= 16) return find_split_n<16>(begin, end, cbox);
    if (config_.bins <= 32) return find_split_n<32>(begin, end, cbox);
    if (config_.bins <= 64) return find_split_n<64>(begin, end, cbox);
    return find_split_n<kMaxBins>(begin, end, cbox);
  }

  template <int NB>
  Split find_split_n(uint32_t begin, uint32_t end, const Bounds3& cbox) const {
    const auto s = scales(cbox);
    const int nb = config_.bins;
    BinArray<NB> bins;
    if (end - begin >= uint32_t(config_.parallel_threshold)) {
      // Bin unions and counts are exact, so the reduction order cannot change the result.
      bins = tbb::parallel_reduce(
          tbb::blocked_range<uint32_t>(begin, end, 1024), BinArray<NB>{},
          [&](const tbb::blocked_range<uint32_t>& r, BinArray<NB> acc) {
            bin_range<NB>(r.begin(), r.end(), cbox, s, acc);
            return acc;
          },
          [nb](BinArray<NB> a, const BinArray<NB>& b) {
            for (int ax = 0; ax < 3; ++ax)
              for (int k = 0; k < nb; ++k) a[ax][k].add(b[ax][k]);
            return a;
          });
    } else {
      bin_range<NB>(begin, end, cbox, s, bins);
    }
    Split best;
    for (int a = 0; a < 3; ++a) {
      if (s[a] == 0.0f) continue;
      // Sweep from the right: right_cost[k] = A N of bins (k, nb).
      std::array<float, NB> right_cost;
      std::array<uint32_t, NB> right_count;
      Bounds3 acc;
      uint32_t count = 0;
      for (int k = nb - 1; k > 0; --k) {
        acc.extend(bins[a][k].box);
        count += bins[a][k].count;
        right_cost[k - 1] = acc.surface_area() * float(count);
        right_count[k - 1] = count;
      }
      Bounds3 left;
      count = 0;
      for (int k = 0; k < nb - 1; ++k) {
        left.extend(bins[a][k].box);
        count += bins[a][k].count;
        if (count == 0 || right_count[k] == 0) continue;
        const float cost = left.surface_area() * float(count) + right_cost[k];
        if (best.axis < 0 || cost < best.cost) {
          best.axis = a;
          best.bin = k;
          best.cost = cost;
        }
      }
    }
    if (best.axis >= 0) {
      for (int k = 0; k < nb; ++k) (k <= best.bin ? best.left : best.right).add(bins[best.axis][k]);
    }
    return best;
  }

  uint32_t partition(uint32_t begin, uint32_t end, const Bounds3& cbox, int axis, int bin) const {
    const float scale = scales(cbox)[axis];
    auto* b = ids_.data();
    auto* m = std::partition(b + begin, b + end, [&](uint32_t p) {
      return bin_of(centers_[p][axis], cbox.lo[axis], scale, config_.bins) <= bin;
    });
    return uint32_t(m - b);
  }

  Bin bounds_of(uint32_t begin, uint32_t end) const {
    Bin r;
    for (uint32_t i = begin; i < end; ++i) {
      r.box.extend(boxes_[ids_[i]]);
      r.cbox.extend(centers_[ids_[i]]);
    }
    r.count = end - begin;
    return r;
  }

  std::span<const Bounds3> boxes_;
  std::span<const Vec3> centers_;
  const BvhBuildConfig& config_;
  std::vector<Bvh2Node>& slots_;
  std::vector<uint32_t>& ids_;
};

}  // namespace

int build_binned_sah(std::span<const Bounds3> boxes, std::span<const Vec3> centers,
                     const BvhBuildConfig& config, std::vector<Bvh2Node>& nodes,
                     std::vector<uint32_t>& prim_ids) {
  if (config.bins < 2 || config.bins > kMaxBins)
    throw InputError("BvhBuildConfig.bins = " + std::to_string(config.bins) + ": must be in [2, 256]");
  if (config.max_leaf_size < 1 || config.max_leaf_size > 15)
    throw InputError("BvhBuildConfig.max_leaf_size = " + std::to_string(config.max_leaf_size) +
                     ": must be in [1, 15]");
  if (boxes.size() >= (1u << 27))
    throw InputError("BVH: " + std::to_string(boxes.size()) + " triangles, at most 2^27 supported");
  const uint32_t n = uint32_t(boxes.size());
  nodes.clear();
  prim_ids.resize(n);
  for (uint32_t i = 0; i < n; ++i) prim_ids[i] = i;
  if (n == 0) return 0;

  struct Both { Bounds3 box, cbox; };
  const Both all = tbb::parallel_reduce(
      tbb::blocked_range<uint32_t>(0, n, 4096), Both{},
      [&](const tbb::blocked_range<uint32_t>& r, Both acc) {
        for (uint32_t i = r.begin(); i != r.end(); ++i) { acc.box.extend(boxes[i]); acc.cbox.extend(centers[i]); }
        return acc;
      },
      [](Both a, const Both& b) { a.box.extend(b.box); a.cbox.extend(b.cbox); return a; });

  std::vector<Bvh2Node> slots(2 * size_t(n) - 1);
  Builder(boxes, centers, config, slots, prim_ids).build(0, 0, n, all.box, all.cbox, 1);

  // Compact the scheduling-independent slot layout into depth-first order, siblings adjacent.
  nodes.reserve(2 * size_t(n) - 1);
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
  nodes.shrink_to_fit();
  return depth;
}

}  // namespace rayscout::detail
