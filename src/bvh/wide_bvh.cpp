// WideBvh: collapsing a Bvh2 into 8-wide nodes, and the invariant checker.
#include "rayscout/bvh/wide_bvh.h"

#include <algorithm>
#include <cstring>
#include <string>

#include "rayscout/core/accelerator_options.h"
#include "validate_coverage.h"

namespace rayscout {

WideBvh WideBvh::build(std::span<const Triangle> tris, const BvhBuildConfig& config) {
  return from_bvh2(Bvh2::build(tris, config), tris);
}

WideBvh WideBvh::from_bvh2(const Bvh2& bvh, std::span<const Triangle> tris) {
  WideBvh w;
  if (bvh.nodes.empty()) return w;
  w.bounds = bvh.nodes[0].bounds;
  w.split_references = bvh.split_references;
  w.prim_ids.reserve(bvh.prim_ids.size());
  w.leaf_blocks.reserve(bvh.prim_ids.size() / 3 + 1);
  w.nodes.reserve(bvh.nodes.size() / 4 + 1);
  struct Item { uint32_t wide, bvh2; int depth; };
  std::vector<Item> stack{{0, 0, 1}};
  w.nodes.emplace_back();
  w.source_node.push_back(0);
  while (!stack.empty()) {
    const Item it = stack.back();
    stack.pop_back();
    w.depth_ = std::max(w.depth_, it.depth);
    // Open the largest-area inner child until 8 children (Embree's BVH8 collapse).
    uint32_t kids[kWideWidth];
    int k = 0;
    const Bvh2Node& src = bvh.nodes[it.bvh2];
    if (src.is_leaf()) {
      kids[k++] = it.bvh2;
    } else {
      kids[k++] = src.first;
      kids[k++] = src.first + 1;
    }
    while (k < kWideWidth) {
      int best = -1;
      float best_area = -1.0f;
      for (int c = 0; c < k; ++c) {
        const Bvh2Node& n = bvh.nodes[kids[c]];
        if (!n.is_leaf() && n.bounds.surface_area() > best_area) {
          best = c;
          best_area = n.bounds.surface_area();
        }
      }
      if (best < 0) break;
      const uint32_t first = bvh.nodes[kids[best]].first;
      for (int c = k; c > best + 1; --c) kids[c] = kids[c - 1];  // keep left-to-right order
      kids[best] = first;
      kids[best + 1] = first + 1;
      ++k;
    }
    WideNode node{};
    for (int c = 0; c < kWideWidth; ++c) {
      node.lo_x[c] = node.lo_y[c] = node.lo_z[c] = kInfinity;
      node.hi_x[c] = node.hi_y[c] = node.hi_z[c] = -kInfinity;
    }
    node.count = uint32_t(k);
    std::vector<Item> children;
    for (int c = 0; c < k; ++c) {
      const Bvh2Node& n = bvh.nodes[kids[c]];
      node.lo_x[c] = n.bounds.lo.x; node.lo_y[c] = n.bounds.lo.y; node.lo_z[c] = n.bounds.lo.z;
      node.hi_x[c] = n.bounds.hi.x; node.hi_y[c] = n.bounds.hi.y; node.hi_z[c] = n.bounds.hi.z;
      if (n.is_leaf()) {
        // Pack leaves into the free lanes of the last block unless that makes the leaf span
        // more blocks than it needs (more block tests); padding lanes stay kInvalidId.
        constexpr uint32_t W = kTriangleBlockWidth;
        if (w.prim_ids.size() + n.count + W > WideRef::kMaxFirst)
          throw InputError("WideBvh: more than 2^27 leaf slots (too many triangles or pre-split references)");
        uint32_t first = uint32_t(w.prim_ids.size());
        if ((first % W + n.count + W - 1) / W > (n.count + W - 1) / W) first = (first + W - 1) / W * W;
        w.prim_ids.resize((first + n.count + W - 1) / W * W, kInvalidId);
        w.leaf_blocks.resize(w.prim_ids.size() / W);
        for (uint32_t k = 0; k < n.count; ++k) {
          const uint32_t id = bvh.prim_ids[n.first + k];
          w.prim_ids[first + k] = id;
          w.leaf_blocks[(first + k) / W].set(int((first + k) % W), tris[id]);
        }
        w.prim_ids.resize(first + n.count);  // the next leaf may use the rest of this block
        node.child[c] = WideRef::leaf(first, n.count);
      } else {
        node.child[c] = uint32_t(w.nodes.size());
        w.nodes.emplace_back();
        w.source_node.push_back(kids[c]);
        children.push_back({node.child[c], kids[c], it.depth + 1});
      }
    }
    w.nodes[it.wide] = node;
    for (size_t c = children.size(); c-- > 0;) stack.push_back(children[c]);
  }
  w.prim_ids.resize(w.leaf_blocks.size() * kTriangleBlockWidth, kInvalidId);
  // Unused lanes get a copy of a real triangle of their block: finite values, masked off anyway.
  for (size_t s = 0; s < w.prim_ids.size(); ++s)
    if (w.prim_ids[s] == kInvalidId) {
      const size_t b = s / kTriangleBlockWidth;
      for (size_t k = b * kTriangleBlockWidth; k < (b + 1) * kTriangleBlockWidth; ++k)
        if (w.prim_ids[k] != kInvalidId) { w.leaf_blocks[b].set(int(s % kTriangleBlockWidth), w.leaf_triangle(k)); break; }
    }
  w.prim_ids.shrink_to_fit();
  w.leaf_blocks.shrink_to_fit();
  w.nodes.shrink_to_fit();
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
          const Bounds3 tb = leaf_triangle(k).bounds();
          if (split_references ? Bounds3{max(tb.lo, box.lo), min(tb.hi, box.hi)}.empty() : !box.contains(tb))
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
