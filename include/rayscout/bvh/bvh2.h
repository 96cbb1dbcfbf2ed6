// Bvh2: the binary bounding volume hierarchy, its binned SAH build and single-ray traversal.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "rayscout/bvh/bvh_build_config.h"
#include "rayscout/bvh/cull_interval.h"
#include "rayscout/core/bounds3.h"
#include "rayscout/core/ray.h"
#include "rayscout/core/trace_stats.h"
#include "rayscout/core/triangle.h"

namespace rayscout {

/// One node of a Bvh2, 32 bytes. Children of an inner node are adjacent (first, first + 1).
struct Bvh2Node {
  Bounds3 bounds;   ///< box of every triangle below the node
  uint32_t first;   ///< inner: index of the left child (right = first + 1); leaf: first index into prim_ids
  uint16_t count;   ///< 0 = inner node; else number of triangles of the leaf
  uint8_t axis;     ///< split axis of an inner node (recorded only: traversal orders children by entry distance)
  uint8_t pad;
  bool is_leaf() const { return count != 0; }
};
static_assert(sizeof(Bvh2Node) == 32);

/// Binary BVH built with binned SAH (Wald 2007), parallel with oneTBB. The builder sees only
/// triangle boxes and centroids. Traversal uses a robust slab test (Ize 2013; it keeps every
/// box core's intersect_box keeps, see src/bvh/box_test.h) and core's watertight triangle
/// test, so hits are bit-identical to BruteForce (but for two kinds of grazing rays: docs/bvh.md).
class Bvh2 {
 public:
  std::vector<Bvh2Node> nodes;     ///< nodes[0] = root; empty for an empty triangle set
  std::vector<uint32_t> prim_ids;  ///< leaf ranges index this; values are triangle ids
  /// leaf_tris[k] = tris[prim_ids[k]]: a leaf's triangles side by side, so a leaf costs no
  /// gather through the ids (the ids are read only for a closest hit's tie-break and result).
  std::vector<Triangle> leaf_tris;
  /// Built with BvhBuildConfig::presplit > 0: a triangle may appear in several leaves (never
  /// twice in one), and a leaf box may hold only part of a triangle.
  bool split_references = false;

  /// Builds over tris (copied in leaf order, see leaf_tris). The same input gives the same
  /// tree for any thread count.
  static Bvh2 build(std::span<const Triangle> tris, const BvhBuildConfig& config = {});

  /// Closest hit of one ray (tmin <= t <= tmax, ties to the smaller id) against the
  /// triangles the tree was built over. Traversal starts from the `start` nodes in order (start[0]
  /// first), each hit one once the stack runs empty; they are box tested a SIMD group at a time
  /// (8 or 16), so a group after an any-hit is never tested and a hit entry beyond the current
  /// closest hit is skipped; an empty span means the root. This is the entry ray
  /// classification (shafts) uses with its candidate lists. With CaptureStats,
  /// stats (non-null) receives traversal_steps (nodes visited), ray_box_tests, ray_tri_tests;
  /// it does not count stats->rays.
  template <bool CaptureStats>
  Hit intersect(const Ray& ray, std::span<const uint32_t> start, TraceStats* stats) const;
  /// Any hit with tmin <= t <= tmax, stops at the first one. Same start and stats as intersect.
  template <bool CaptureStats>
  bool occluded(const Ray& ray, std::span<const uint32_t> start, TraceStats* stats) const;
  /// The widened interval the traversal box-tests with for this ray (over the root's box).
  CullInterval cull_interval(const Ray& ray) const {
    return CullInterval(nodes.empty() ? Bounds3{} : nodes[0].bounds, ray);
  }

  /// Checks the invariants against the triangles the tree was built over: every triangle id
  /// in [0, tris.size()) exactly once (at least once and once per leaf with
  /// split_references), leaf_tris the triangles of prim_ids, each leaf's triangles inside its
  /// box (touching it with split_references), children inside their parent, every node
  /// reachable exactly once, child indices in range. Returns "" when all hold, else the first
  /// violation.
  std::string validate(std::span<const Triangle> tris) const;
  /// Edges on the longest root-to-leaf path (0 for a lone leaf).
  int depth() const { return depth_; }
  /// Bytes of the tree alone: nodes and prim_ids.
  size_t tree_bytes() const { return nodes.capacity() * sizeof(Bvh2Node) + prim_ids.capacity() * sizeof(uint32_t); }
  /// Bytes of everything: the tree and its triangle copy.
  size_t memory_bytes() const { return tree_bytes() + leaf_tris.capacity() * sizeof(Triangle); }

 private:
  friend class WideBvh;
  /// build without the triangle copy: for a collapse that makes its own (WideBvh::build),
  /// whose build time the copy would only add to. Not traversable.
  static Bvh2 build_tree(std::span<const Triangle> tris, const BvhBuildConfig& config);

  int depth_ = 0;
};

}  // namespace rayscout
