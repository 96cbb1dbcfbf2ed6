// Bvh2: build (binned SAH over triangle boxes) and the invariant checker.
#include "rayscout/bvh/bvh2.h"

#include <algorithm>
#include <string>

#include <tbb/parallel_for.h>

#include "binned_sah_builder.h"

namespace rayscout {

Bvh2 Bvh2::build(std::span<const Triangle> tris, const BvhBuildConfig& config) {
  std::vector<Bounds3> boxes(tris.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, tris.size(), 4096), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) boxes[i] = tris[i].bounds();
  });
  Bvh2 bvh;
  bvh.depth_ = detail::build_binned_sah(boxes, config, bvh.nodes, bvh.prim_ids);
  return bvh;
}

void Bvh2::update_depth() {
  depth_ = 0;
  if (nodes.empty()) return;
  std::vector<std::pair<uint32_t, int>> stack{{0, 0}};
  while (!stack.empty()) {
    auto [n, d] = stack.back();
    stack.pop_back();
    depth_ = std::max(depth_, d);
    if (n >= nodes.size() || nodes[n].is_leaf() || nodes[n].first + 1 >= nodes.size()) continue;
    if (d > int(nodes.size())) return;  // a cycle; validate() reports it
    stack.push_back({nodes[n].first, d + 1});
    stack.push_back({nodes[n].first + 1, d + 1});
  }
}

std::string Bvh2::validate(size_t triangle_count) const {
  if (nodes.empty())
    return triangle_count == 0 && prim_ids.empty() ? "" : "no nodes but " + std::to_string(triangle_count) + " triangles";
  if (prim_ids.size() != triangle_count)
    return "prim_ids has " + std::to_string(prim_ids.size()) + " entries, expected " + std::to_string(triangle_count);
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
        if (prim_seen[p]++) return at + "triangle " + std::to_string(p) + " appears twice";
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
  if (leaf_prims != triangle_count)
    return "leaves hold " + std::to_string(leaf_prims) + " triangles, expected " + std::to_string(triangle_count);
  for (size_t i = 0; i < nodes.size(); ++i)
    if (!node_seen[i]) return "node " + std::to_string(i) + " unreachable";
  return "";
}

}  // namespace rayscout
