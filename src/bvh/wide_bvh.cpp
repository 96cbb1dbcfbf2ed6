// WideBvh: collapsing a Bvh2 into 8-wide nodes, and the invariant checker.
#include "rayscout/bvh/wide_bvh.h"

#include <algorithm>
#include <cstring>
#include <memory>
#include <string>

#include "rayscout/core/input_error.h"
#include "validate_coverage.h"

namespace rayscout {

namespace {

// TriangleBlocks that n consecutive leaf slots from a block's first lane span.
constexpr uint32_t blocks_for(uint32_t n) { return (n + kTriangleBlockWidth - 1) / kTriangleBlockWidth; }

// A child slot chosen by the collapse: Bvh2 node `node` becomes one wide child, a leaf
// holding every triangle below it (leaf = true) or a wide node.
struct Slot {
  uint32_t node;
  bool leaf;
};

// Greedy collapse of Bvh2 node n: open the largest-area inner child until 8 slots.
int greedy_slots(const Bvh2& bvh, uint32_t n, Slot* out) {
  uint32_t kids[kWideWidth];
  int k = 0;
  const Bvh2Node& src = bvh.nodes[n];
  if (src.is_leaf()) {
    kids[k++] = n;
  } else {
    kids[k++] = src.first;
    kids[k++] = src.first + 1;
  }
  while (k < kWideWidth) {
    int best = -1;
    float best_area = -1.0f;
    for (int c = 0; c < k; ++c) {
      const Bvh2Node& m = bvh.nodes[kids[c]];
      if (!m.is_leaf() && m.bounds.surface_area() > best_area) {
        best = c;
        best_area = m.bounds.surface_area();
      }
    }
    if (best < 0) break;
    const uint32_t first = bvh.nodes[kids[best]].first;
    for (int c = k; c > best + 1; --c) kids[c] = kids[c - 1];  // keep left-to-right order
    kids[best] = first;
    kids[best + 1] = first + 1;
    ++k;
  }
  for (int c = 0; c < k; ++c) out[c] = {kids[c], bvh.nodes[kids[c]].is_leaf()};
  return k;
}

// The cheapest spread of the two children of an inner Bvh2 node over at most `slots` child
// slots (2..8) of a wide node, given their plans cl and cr (SahCollapse::cost_ rows).
struct Spread {
  float cost;      // cl[left_slots - 1] + cr[slots - left_slots - 1]
  int left_slots;  // slots given to the left child (ties: the fewest)
};
Spread best_spread(const float* cl, const float* cr, int slots) {
  Spread best{kInfinity, 1};
  for (int left = 1; left < slots; ++left) {
    const float v = cl[left - 1] + cr[slots - left - 1];
    if (v < best.cost) best = {v, left};
  }
  return best;
}

// Pre-order of the Bvh2's nodes: from_bvh2 takes any Bvh2, whose children need not follow
// their parents in the node array, so a walk gives the order instead of the indices.
std::vector<uint32_t> preorder(const Bvh2& bvh) {
  std::vector<uint32_t> order;
  order.reserve(bvh.nodes.size());
  std::vector<uint32_t> stack{0};
  while (!stack.empty()) {
    const uint32_t i = stack.back();
    stack.pop_back();
    order.push_back(i);
    if (!bvh.nodes[i].is_leaf()) {
      stack.push_back(bvh.nodes[i].first);
      stack.push_back(bvh.nodes[i].first + 1);
    }
  }
  return order;
}

// The SAH collapse plan (Ylitie, Karras, Laine 2017, sec. 4.1): cost[n][i] = least SAH cost
// of the subtree of Bvh2 node n using at most i + 1 slots of its wide parent, areas not
// normalised (only comparisons matter).
class SahCollapse {
 public:
  SahCollapse(const Bvh2& bvh, const BvhBuildConfig& config) : bvh_(bvh) {
    const size_t n = bvh.nodes.size();
    cost_.resize(n * kWideWidth);
    split_.resize(n * kWideWidth);
    as_leaf_.resize(n);
    refs_.resize(n);
    const std::vector<uint32_t> order = preorder(bvh);
    const uint32_t max_leaf = uint32_t(std::clamp(config.collapse_max_leaf, 1, kBvhMaxLeafSize));
    // Backwards through the pre-order: children are planned before their parent.
    for (size_t o = order.size(); o-- > 0;) plan(order[o], config, max_leaf);
  }

  // The slots of the wide node made from inner Bvh2 node n.
  int slots(uint32_t n, Slot* out) const {
    const Bvh2Node& nd = bvh_.nodes[n];
    if (nd.is_leaf()) {
      out[0] = {n, true};
      return 1;
    }
    int k = 0;
    // Spread the two children over the 8 slots at the least cost (the table's choice).
    const Spread spread = best_spread(row(nd.first), row(nd.first + 1), kWideWidth);
    emit(nd.first, spread.left_slots, out, k);
    emit(nd.first + 1, kWideWidth - spread.left_slots, out, k);
    return k;
  }

  // The distinct triangle ids below Bvh2 node n, sorted (pre-split pieces of one triangle merge).
  void collect(uint32_t n, std::vector<uint32_t>& ids) const {
    std::vector<uint32_t> stack{n};
    while (!stack.empty()) {
      const Bvh2Node& nd = bvh_.nodes[stack.back()];
      stack.pop_back();
      if (nd.is_leaf()) {
        ids.insert(ids.end(), bvh_.prim_ids.begin() + nd.first, bvh_.prim_ids.begin() + nd.first + nd.count);
      } else {
        stack.push_back(nd.first);
        stack.push_back(nd.first + 1);
      }
    }
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  }

 private:
  const float* row(uint32_t n) const { return &cost_[size_t(n) * kWideWidth]; }

  // Fills node i's row of cost_ and split_, as_leaf_[i] and refs_[i]; its children's are done.
  void plan(uint32_t i, const BvhBuildConfig& config, uint32_t max_leaf) {
    const Bvh2Node& nd = bvh_.nodes[i];
    const float area = nd.bounds.surface_area();
    float* cost = &cost_[size_t(i) * kWideWidth];
    uint8_t* split = &split_[size_t(i) * kWideWidth];
    auto leaf_cost = [&](uint32_t count) {
      return area * (config.collapse_leaf_cost + config.collapse_block_cost * float(blocks_for(count)));
    };
    if (nd.is_leaf()) {
      refs_[i] = nd.count;
      as_leaf_[i] = 1;
      for (int s = 0; s < kWideWidth; ++s) cost[s] = leaf_cost(nd.count), split[s] = 0;
      return;
    }
    const uint32_t l = nd.first, r = nd.first + 1;
    // spread[j]: the two children over at most j + 1 slots (j >= 1).
    Spread spread[kWideWidth];
    for (int j = 1; j < kWideWidth; ++j) spread[j] = best_spread(row(l), row(r), j + 1);
    // One slot: a wide node of its own, or a leaf of every reference below when that is cheaper.
    float single = area * config.collapse_node_cost + spread[kWideWidth - 1].cost;
    as_leaf_[i] = 0;
    // Pieces of one pre-split triangle count once per piece here (an upper bound: the
    // leaf may end up smaller), which spares gathering the ids of every small subtree.
    refs_[i] = refs_[l] + refs_[r];
    if (refs_[i] <= max_leaf && leaf_cost(refs_[i]) <= single) {
      single = leaf_cost(refs_[i]);
      as_leaf_[i] = 1;
    }
    cost[0] = single;
    split[0] = 0;
    // More slots: the cheaper of the spread and what fewer slots already allow.
    for (int j = 1; j < kWideWidth; ++j) {
      if (spread[j].cost < cost[j - 1]) {
        cost[j] = spread[j].cost, split[j] = uint8_t(spread[j].left_slots);
      } else {
        cost[j] = cost[j - 1], split[j] = split[j - 1];
      }
    }
  }

  // Emits the subtree of m into at most `budget` slots.
  void emit(uint32_t m, int budget, Slot* out, int& k) const {
    const uint8_t s = split_[size_t(m) * kWideWidth + (budget - 1)];
    if (s == 0) {
      out[k++] = {m, as_leaf_[m] != 0};
      return;
    }
    const Bvh2Node& nd = bvh_.nodes[m];
    emit(nd.first, s, out, k);
    emit(nd.first + 1, budget - s, out, k);
  }

  const Bvh2& bvh_;
  std::vector<float> cost_;
  std::vector<uint8_t> split_;  // 0: one slot; else slots given to the left child
  std::vector<uint8_t> as_leaf_;
  std::vector<uint32_t> refs_;  // leaf references below the node (pre-split pieces counted apart; < 2^27)
};

// A wide node with no children: every slot's box empty (lo = +inf, hi = -inf), as the SIMD
// box test needs of unused slots.
WideNode empty_wide_node() {
  WideNode node{};
  for (int c = 0; c < kWideWidth; ++c) {
    node.lo_x[c] = node.lo_y[c] = node.lo_z[c] = kInfinity;
    node.hi_x[c] = node.hi_y[c] = node.hi_z[c] = -kInfinity;
  }
  return node;
}

void set_child_bounds(WideNode& node, int c, const Bounds3& b) {
  node.lo_x[c] = b.lo.x; node.lo_y[c] = b.lo.y; node.lo_z[c] = b.lo.z;
  node.hi_x[c] = b.hi.x; node.hi_y[c] = b.hi.y; node.hi_z[c] = b.hi.z;
}

// Appends a leaf of the triangles `ids` to w's leaf slots and returns its WideRef. It goes
// into the free lanes of the last block unless that makes it span more blocks than it needs
// (more block tests); lanes skipped stay kInvalidId.
uint32_t append_leaf(WideBvh& w, std::span<const uint32_t> ids, std::span<const Triangle> tris) {
  constexpr uint32_t W = kTriangleBlockWidth;
  const uint32_t count = uint32_t(ids.size());
  if (w.prim_ids.size() + count + W > WideRef::kMaxFirst)
    throw InputError("WideBvh: more than 2^27 leaf slots (too many triangles or pre-split references)");
  uint32_t first = uint32_t(w.prim_ids.size());
  if (blocks_for(first % W + count) > blocks_for(count)) first = blocks_for(first) * W;
  w.prim_ids.resize(blocks_for(first + count) * W, kInvalidId);
  w.leaf_blocks.resize(w.prim_ids.size() / W);
  for (uint32_t j = 0; j < count; ++j) {
    w.prim_ids[first + j] = ids[j];
    w.leaf_blocks[(first + j) / W].set(int((first + j) % W), tris[ids[j]]);
  }
  w.prim_ids.resize(first + count);  // the next leaf may use the rest of this block
  return WideRef::leaf(first, count);
}

// Pads prim_ids to whole blocks and gives every unused lane (kInvalidId) a copy of a real
// triangle of its block: finite values, masked off anyway.
void fill_padding_lanes(WideBvh& w) {
  w.prim_ids.resize(w.leaf_blocks.size() * kTriangleBlockWidth, kInvalidId);
  for (size_t s = 0; s < w.prim_ids.size(); ++s)
    if (w.prim_ids[s] == kInvalidId) {
      const size_t b = s / kTriangleBlockWidth;
      for (size_t k = b * kTriangleBlockWidth; k < (b + 1) * kTriangleBlockWidth; ++k)
        if (w.prim_ids[k] != kInvalidId) {
          w.leaf_blocks[b].set(int(s % kTriangleBlockWidth), w.leaf_triangle(k));
          break;
        }
    }
}

}  // namespace

WideBvh WideBvh::build(std::span<const Triangle> tris, const BvhBuildConfig& config) {
  return from_bvh2(Bvh2::build_tree(tris, config), tris, config);
}

WideBvh WideBvh::from_bvh2(const Bvh2& bvh, std::span<const Triangle> tris, const BvhBuildConfig& config,
                           std::vector<uint32_t>* source_node) {
  WideBvh w;
  if (bvh.nodes.empty()) return w;
  w.bounds = bvh.nodes[0].bounds;
  w.split_references = bvh.split_references;
  // Upper bounds, so the buffers never grow by copying: a leaf of n references takes at most
  // ceil(n / 4) blocks (merged leaves no more than their parts), and every wide node comes
  // from a different inner Bvh2 node.
  const size_t bvh2_leaves = (bvh.nodes.size() + 1) / 2;
  w.leaf_blocks.reserve((bvh.prim_ids.size() + 3 * bvh2_leaves) / kTriangleBlockWidth + 1);
  w.prim_ids.reserve(w.leaf_blocks.capacity() * kTriangleBlockWidth);
  w.nodes.reserve(bvh2_leaves);
  if (source_node) source_node->assign(1, 0);
  std::unique_ptr<SahCollapse> sah;
  if (config.collapse == CollapseMethod::Sah) sah = std::make_unique<SahCollapse>(bvh, config);
  struct Item { uint32_t wide, bvh2; int depth; };
  std::vector<Item> stack{{0, 0, 1}};
  w.nodes.emplace_back();
  std::vector<uint32_t> ids;
  while (!stack.empty()) {
    const Item it = stack.back();
    stack.pop_back();
    w.depth_ = std::max(w.depth_, it.depth);
    Slot kids[kWideWidth];
    const int k = sah ? sah->slots(it.bvh2, kids) : greedy_slots(bvh, it.bvh2, kids);
    WideNode node = empty_wide_node();
    node.count = uint32_t(k);
    Item children[kWideWidth];
    int inner = 0;
    for (int c = 0; c < k; ++c) {
      const Bvh2Node& n = bvh.nodes[kids[c].node];
      set_child_bounds(node, c, n.bounds);
      if (kids[c].leaf) {
        ids.clear();
        if (n.is_leaf()) {
          ids.assign(bvh.prim_ids.begin() + n.first, bvh.prim_ids.begin() + n.first + n.count);
        } else {
          sah->collect(kids[c].node, ids);
        }
        node.child[c] = append_leaf(w, ids, tris);
      } else {
        node.child[c] = uint32_t(w.nodes.size());
        w.nodes.emplace_back();
        if (source_node) source_node->push_back(kids[c].node);
        children[inner++] = {node.child[c], kids[c].node, it.depth + 1};
      }
    }
    w.nodes[it.wide] = node;
    for (int c = inner; c-- > 0;) stack.push_back(children[c]);
  }
  fill_padding_lanes(w);
  // No shrink_to_fit: copying into exact-size buffers touches fresh pages, a large part of a
  // cold build; the reserve's unused tail is never touched (memory_bytes counts sizes).
  return w;
}

Bounds3 WideBvh::ref_bounds(uint32_t ref) const {
  Bounds3 b;
  if (WideRef::is_leaf(ref)) {
    for (uint32_t i = WideRef::leaf_first(ref); i < WideRef::leaf_first(ref) + WideRef::leaf_count(ref); ++i)
      b.extend(leaf_triangle(i).bounds());
  } else {
    for (uint32_t c = 0; c < nodes[ref].count; ++c) b.extend(nodes[ref].child_bounds(int(c)));
  }
  return b;
}

std::string WideBvh::validate(size_t triangle_count) const {
  if (nodes.empty())
    return triangle_count == 0 ? "" : "no nodes but " + std::to_string(triangle_count) + " triangles";
  if (prim_ids.size() != leaf_blocks.size() * kTriangleBlockWidth)
    return "prim_ids has " + std::to_string(prim_ids.size()) + " slots for " + std::to_string(leaf_blocks.size()) + " blocks";
  std::vector<uint8_t> node_seen(nodes.size(), 0), prim_seen(triangle_count, 0), slot_seen(prim_ids.size(), 0);
  std::vector<uint32_t> stack{0};
  node_seen[0] = 1;
  size_t leaf_prims = 0;
  while (!stack.empty()) {
    const uint32_t i = stack.back();
    stack.pop_back();
    const WideNode& n = nodes[i];
    const std::string at = "wide node " + std::to_string(i) + ": ";
    if (n.count < 1 || n.count > uint32_t(kWideWidth)) return at + "child count " + std::to_string(n.count);
    for (uint32_t c = 0; c < n.count; ++c) {
      const uint32_t ref = n.child[c];
      const Bounds3 box = n.child_bounds(int(c));
      const std::string slot = at + "slot " + std::to_string(c) + ": ";
      if (WideRef::is_leaf(ref)) {
        const uint32_t first = WideRef::leaf_first(ref), count = WideRef::leaf_count(ref);
        if (count == 0) return slot + "empty leaf";
        if (size_t(first) + count > prim_ids.size()) return slot + "leaf range beyond prim_ids";
        for (uint32_t k = first; k < first + count; ++k) {
          const uint32_t p = prim_ids[k];
          if (p >= triangle_count) return slot + "triangle id " + std::to_string(p) + " out of range";
          if (prim_seen[p]++ && !split_references) return slot + "triangle " + std::to_string(p) + " appears twice";
          if (slot_seen[k]++) return slot + "leaf slot " + std::to_string(k) + " shared by two leaves";
          if (detail::outside_leaf_box(leaf_triangle(k).bounds(), box, split_references))
            return slot + "triangle " + std::to_string(p) + " outside the child box";
          ++leaf_prims;
        }
        continue;
      }
      if (ref >= nodes.size()) return slot + "child node " + std::to_string(ref) + " out of range";
      if (node_seen[ref]) return slot + "child node " + std::to_string(ref) + " reached twice";
      node_seen[ref] = 1;
      if (nodes[ref].count < 1 || nodes[ref].count > uint32_t(kWideWidth))
        return slot + "child node " + std::to_string(ref) + " has " + std::to_string(nodes[ref].count) + " children";
      if (!box.contains(ref_bounds(ref))) return slot + "child node " + std::to_string(ref) + " not inside its box";
      stack.push_back(ref);
    }
  }
  return detail::validate_coverage(prim_seen, node_seen, leaf_prims, triangle_count, split_references, "wide node");
}

}  // namespace rayscout
