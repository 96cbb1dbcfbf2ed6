// TreeView: a BVH (binary or wide) flattened for candidate-list construction.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "rayscout/bvh/bvh2.h"
#include "rayscout/bvh/wide_bvh.h"
#include "rayscout/core/bounds3.h"

namespace rayscout {

/// The tree the candidate lists index, in one shape for both BVHs: node i has a box, the
/// reference a traversal accepts as a start entry (Bvh2 node id, or a WideRef), and its
/// children (none for a leaf). Used only while building; borrowed from nothing.
struct TreeView {
  std::vector<Bounds3> bounds;
  std::vector<uint32_t> ref;          ///< start-entry value of node i
  std::vector<uint32_t> child_begin;  ///< children of i: child[child_begin[i] .. child_begin[i+1])
  std::vector<uint32_t> child;
  std::vector<int8_t> split_axis;     ///< Bvh2: left child is nearer when dir[axis] > 0; -1 = order by box centre
  int arity = 2;                      ///< k of the k-ary BVH (min hit probability (k-1)/k)
  bool split_order = true;            ///< children ordered by split_axis (else by box centre)
  uint32_t root = 0;                  ///< node index of the root

  size_t size() const { return bounds.size(); }
  bool is_leaf(uint32_t i) const { return child_begin[i] == child_begin[i + 1]; }
  std::span<const uint32_t> children(uint32_t i) const {
    return {child.data() + child_begin[i], child.data() + child_begin[i + 1]};
  }

  /// Node i = Bvh2 node i. levels > 1: a node's children are its Bvh2 descendants `levels`
  /// generations down (or leaves above that), so lists skip intermediate levels and the build
  /// walks a shallower tree; children are then ordered by box centre. arity stays 2.
  static TreeView from_bvh2(const Bvh2& bvh, int levels = 1);
  /// Wide nodes first (index = node id), then one entry per leaf reference.
  static TreeView from_wide(const WideBvh& bvh);
};

}  // namespace rayscout
