// What both trees' validate() share: the leaf box rule, and the end (every triangle in a
// leaf, every node reached).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "rayscout/core/bounds3.h"

namespace rayscout::detail {

/// True when a leaf triangle with box tri_box breaks the rule of its leaf's box: it must lie
/// inside it, or, as a split reference (a clipped piece of the triangle), at least touch it.
inline bool outside_leaf_box(const Bounds3& tri_box, const Bounds3& leaf_box, bool split_references) {
  return split_references ? Bounds3{max(tri_box.lo, leaf_box.lo), min(tri_box.hi, leaf_box.hi)}.empty()
                          : !leaf_box.contains(tri_box);
}

/// "" when leaves hold each of the triangle_count triangles (exactly once unless references
/// are split) and every node was reached; else what is wrong. node_label names the node kind.
inline std::string validate_coverage(const std::vector<uint8_t>& prim_seen, const std::vector<uint8_t>& node_seen,
                                     size_t leaf_prims, size_t triangle_count, bool split_references,
                                     const std::string& node_label) {
  if (!split_references && leaf_prims != triangle_count)
    return "leaves hold " + std::to_string(leaf_prims) + " triangles, expected " + std::to_string(triangle_count);
  for (size_t p = 0; p < triangle_count; ++p)
    if (!prim_seen[p]) return "triangle " + std::to_string(p) + " in no leaf";
  for (size_t i = 0; i < node_seen.size(); ++i)
    if (!node_seen[i]) return node_label + " " + std::to_string(i) + " unreachable";
  return "";
}

}  // namespace rayscout::detail
