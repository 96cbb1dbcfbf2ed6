// Bvh2: build (binned SAH over triangle boxes) and the invariant checker.
#include "rayscout/bvh/bvh2.h"

#include <algorithm>
#include <cstring>
#include <string>

#include <tbb/parallel_for.h>

#include "binned_sah_builder.h"
#include "presplit.h"
#include "validate_coverage.h"

namespace rayscout {

Bvh2 Bvh2::build(std::span<const Triangle> tris, const BvhBuildConfig& config) {
  Bvh2 bvh = build_tree(tris, config);
  bvh.leaf_tris.resize(bvh.prim_ids.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, bvh.prim_ids.size(), 16384), [&](const auto& r) {
    for (size_t k = r.begin(); k != r.end(); ++k) bvh.leaf_tris[k] = tris[bvh.prim_ids[k]];
  });
  return bvh;
}

Bvh2 Bvh2::build_tree(std::span<const Triangle> tris, const BvhBuildConfig& config) {
  detail::PrimReferences refs = detail::presplit_triangles(tris, config.presplit, config.presplit_max_pieces);
  Bvh2 bvh;
  bvh.depth_ = detail::build_binned_sah(refs.boxes, config, bvh.nodes, bvh.prim_ids);
  if (!(config.presplit > 0.0f)) return bvh;  // references are the triangles themselves
  bvh.split_references = true;
  // References to triangle ids; two pieces of one triangle in a leaf become one entry.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, bvh.nodes.size(), 4096), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      Bvh2Node& n = bvh.nodes[i];
      if (!n.is_leaf()) continue;
      uint32_t* ids = bvh.prim_ids.data() + n.first;
      uint16_t kept = 0;
      for (uint16_t k = 0; k < n.count; ++k) {
        const uint32_t id = refs.ref_tri[ids[k]];
        if (std::find(ids, ids + kept, id) == ids + kept) ids[kept++] = id;
      }
      for (uint16_t k = kept; k < n.count; ++k) ids[k] = ids[0];  // unreferenced filler
      n.count = kept;
    }
  });
  return bvh;
}

std::string Bvh2::validate(std::span<const Triangle> tris) const {
  const size_t triangle_count = tris.size();
  if (nodes.empty())
    return triangle_count == 0 && prim_ids.empty() ? "" : "no nodes but " + std::to_string(triangle_count) + " triangles";
  if (split_references ? prim_ids.size() < triangle_count : prim_ids.size() != triangle_count)
    return "prim_ids has " + std::to_string(prim_ids.size()) + " entries, expected " + std::to_string(triangle_count);
  if (leaf_tris.size() != prim_ids.size())
    return "leaf_tris has " + std::to_string(leaf_tris.size()) + " entries, prim_ids " + std::to_string(prim_ids.size());
  std::vector<uint8_t> node_seen(nodes.size(), 0), prim_seen(triangle_count, 0);
  std::vector<uint32_t> stack{0};
  node_seen[0] = 1;
  size_t leaf_prims = 0;
  while (!stack.empty()) {
    const uint32_t i = stack.back();
    stack.pop_back();
    const Bvh2Node& n = nodes[i];
    const std::string at = "node " + std::to_string(i) + ": ";
    if (n.is_leaf()) {
      if (size_t(n.first) + n.count > prim_ids.size()) return at + "leaf range beyond prim_ids";
      for (uint32_t k = n.first; k < n.first + n.count; ++k) {
        const uint32_t p = prim_ids[k];
        if (p >= triangle_count) return at + "triangle id " + std::to_string(p) + " out of range";
        if (prim_seen[p]++ && !split_references) return at + "triangle " + std::to_string(p) + " appears twice";
        if (std::find(prim_ids.begin() + n.first, prim_ids.begin() + k, p) != prim_ids.begin() + k)
          return at + "triangle " + std::to_string(p) + " twice in one leaf";
        if (detail::outside_leaf_box(tris[p].bounds(), n.bounds, split_references))
          return at + "triangle " + std::to_string(p) + " outside the leaf box";
        if (std::memcmp(&leaf_tris[k], &tris[p], sizeof(Triangle)) != 0)
          return at + "leaf_tris[" + std::to_string(k) + "] is not triangle " + std::to_string(p);
        ++leaf_prims;
      }
      continue;
    }
    if (size_t(n.first) + 1 >= nodes.size()) return at + "child index " + std::to_string(n.first) + " out of range";
    for (uint32_t c = n.first; c <= n.first + 1; ++c) {
      if (node_seen[c]) return at + "child " + std::to_string(c) + " reached twice (cycle or shared child)";
      node_seen[c] = 1;
      if (!n.bounds.contains(nodes[c].bounds)) return at + "child " + std::to_string(c) + " not inside its parent";
      stack.push_back(c);
    }
  }
  return detail::validate_coverage(prim_seen, node_seen, leaf_prims, triangle_count, split_references, "node");
}

}  // namespace rayscout
