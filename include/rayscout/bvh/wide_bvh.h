// WideBvh: the 8-wide BVH collapsed from a Bvh2, traversed one ray at a time with SIMD box tests.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "rayscout/bvh/bvh2.h"
#include "rayscout/bvh/bvh_build_config.h"
#include "rayscout/bvh/cull_interval.h"
#include "rayscout/core/bounds3.h"
#include "rayscout/core/ray.h"
#include "rayscout/core/trace_stats.h"
#include "rayscout/core/triangle.h"

namespace rayscout {

/// Children per wide node: one AVX2 register of floats (half an AVX-512 one).
inline constexpr int kWideWidth = 8;

/// A child reference inside a WideBvh. Inner child: the wide node id, an index into
/// WideBvh::nodes (bit 31 clear). Leaf: bit 31 set, bits 27..30 = triangle count (1..15),
/// bits 0..26 = first leaf slot: the leaf's triangles are the slots [first, first + count) of
/// WideBvh::prim_ids and leaf_blocks (a leaf may start inside a block when it still spans no
/// more blocks than it needs).
struct WideRef {
  static constexpr uint32_t kLeafBit = 0x80000000u;
  static constexpr uint32_t kCountShift = 27;
  static constexpr uint32_t kMaxCount = 15;  ///< the 4 bits 27..30
  static constexpr uint32_t kMaxFirst = (1u << kCountShift) - 1;
  static bool is_leaf(uint32_t ref) { return (ref & kLeafBit) != 0; }
  static uint32_t leaf(uint32_t first, uint32_t count) { return kLeafBit | (count << kCountShift) | first; }
  static uint32_t leaf_first(uint32_t ref) { return ref & kMaxFirst; }
  static uint32_t leaf_count(uint32_t ref) { return (ref >> kCountShift) & kMaxCount; }
};
static_assert(uint32_t(kBvhMaxLeafSize) <= WideRef::kMaxCount);

/// Triangles per TriangleBlock: one SSE register.
inline constexpr uint32_t kTriangleBlockWidth = 4;

/// Four triangles as structure of arrays (v[vertex][axis][lane]) with their normals
/// (n[axis][lane], Triangle::normal, for the plane distance of core's intersect_triangle), the
/// unit of the SIMD watertight test; slot s of a WideBvh lives in block s / 4, lane s % 4.
/// Lanes no leaf uses (prim_ids = kInvalidId) repeat a triangle of the block and are masked off.
struct alignas(16) TriangleBlock {
  float v[3][3][kTriangleBlockWidth];
  float n[3][kTriangleBlockWidth];
  /// The triangle in lane `lane`.
  Triangle get(int lane) const {
    return {{v[0][0][lane], v[0][1][lane], v[0][2][lane]},
            {v[1][0][lane], v[1][1][lane], v[1][2][lane]},
            {v[2][0][lane], v[2][1][lane], v[2][2][lane]}};
  }
  /// Stores t in lane `lane`.
  void set(int lane, const Triangle& t) {
    const Vec3* p[3] = {&t.v0, &t.v1, &t.v2};
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a) v[k][a][lane] = (*p[k])[a];
    const Vec3 normal = t.normal();
    for (int a = 0; a < 3; ++a) n[a][lane] = normal[a];
  }
};

/// One wide node, 256 bytes: the boxes of up to 8 children as structure of arrays (one SIMD
/// register per bound), their references, and how many slots are used. Slots >= count are
/// unused and must hold empty boxes (lo = +inf, hi = -inf): the SIMD test of finite rays
/// relies on them never being hit (the general test also masks them by count).
struct alignas(64) WideNode {
  float lo_x[kWideWidth], hi_x[kWideWidth];
  float lo_y[kWideWidth], hi_y[kWideWidth];
  float lo_z[kWideWidth], hi_z[kWideWidth];
  uint32_t child[kWideWidth];  ///< WideRef of each used slot
  uint32_t count;              ///< used slots, 1..8 (children are packed at the front)
  uint32_t pad[7];

  /// Box of child slot `slot`.
  Bounds3 child_bounds(int slot) const {
    return {{lo_x[slot], lo_y[slot], lo_z[slot]}, {hi_x[slot], hi_y[slot], hi_z[slot]}};
  }
};
static_assert(sizeof(WideNode) == 256);

/// 8-wide BVH made by collapsing a binned SAH Bvh2, either greedily (each wide node adopts the
/// descendants of the largest-area children until it has 8, as in Wald et al., "Getting rid of
/// packets", 2008, and Embree's BVH8) or by SAH-optimal dynamic programming (Ylitie, Karras,
/// Laine 2017; it may also merge small subtrees into one leaf); see BvhBuildConfig::collapse.
/// It keeps its own copy of the triangles in leaf order, four per TriangleBlock, so traversal
/// reads leaves contiguously and tests four triangles at once (closest hit with AVX2: eight,
/// when a leaf spans two blocks); hits report the original triangle ids and are bit-identical
/// to BruteForce (core's watertight triangle test with the same float operations in every
/// SIMD lane, and a robust box test that keeps every box core's keeps: src/bvh/box_test.h; two
/// kinds of grazing rays excepted, docs/bvh.md).
class WideBvh {
 public:
  std::vector<WideNode> nodes;     ///< nodes[0] = root (empty when there are no triangles)
  std::vector<uint32_t> prim_ids;  ///< leaf slot -> original triangle id (kInvalidId: padding)
  std::vector<TriangleBlock> leaf_blocks;  ///< slot s = leaf_blocks[s / 4] lane s % 4 = tris[prim_ids[s]]
  Bounds3 bounds;                  ///< box of every triangle (the root node's box)
  bool split_references = false;   ///< as Bvh2::split_references

  /// Builds a Bvh2 with config, then collapses it. The default config is the Bvh2's (greedy
  /// collapse, leaves of 4); the `bvh` accelerator builds with wide_bvh_default_config()
  /// (bvh_accelerators.h), which is what the benchmarks measure.
  static WideBvh build(std::span<const Triangle> tris, const BvhBuildConfig& config = {});
  /// Collapses bvh (built over tris) into 8-wide nodes with config.collapse (and its
  /// collapse_* costs); the other fields of config are not used here. When source_node is
  /// given, it receives for each wide node the Bvh2 node it was collapsed from (for tests).
  static WideBvh from_bvh2(const Bvh2& bvh, std::span<const Triangle> tris, const BvhBuildConfig& config = {},
                           std::vector<uint32_t>* source_node = nullptr);

  /// Closest hit of one ray (tmin <= t <= tmax, ties to the smaller id), ordered near-first.
  /// Traversal starts from `start`, a list of WideRefs (wide node ids, or leaf refs as found in
  /// WideNode::child); they are entered without testing their own box (a node's children are
  /// tested when it is visited); start[0] is visited first. Empty span = the root. With
  /// CaptureStats, stats (non-null) receives traversal_steps (entries visited: wide nodes and
  /// leaves), ray_box_tests (one per used child slot tested), ray_tri_tests (one per leaf
  /// triangle in each block test: closest hit tests every triangle of a leaf it enters, any
  /// hit a leaf's blocks up to the first with a hit); not stats->rays.
  template <bool CaptureStats>
  Hit intersect(const Ray& ray, std::span<const uint32_t> start, TraceStats* stats) const;
  /// Any hit with tmin <= t <= tmax, stops at the first one. Same start and stats as intersect.
  template <bool CaptureStats>
  bool occluded(const Ray& ray, std::span<const uint32_t> start, TraceStats* stats) const;
  /// The same two, for a caller that already holds the ray's precomputed RayPrecomp(ray.dir).
  template <bool CaptureStats>
  Hit intersect(const Ray& ray, const RayPrecomp& rp, std::span<const uint32_t> start, TraceStats* stats) const;
  template <bool CaptureStats>
  bool occluded(const Ray& ray, const RayPrecomp& rp, std::span<const uint32_t> start, TraceStats* stats) const;
  /// The widened interval the traversal box-tests with for this ray (over `bounds`).
  CullInterval cull_interval(const Ray& ray) const { return CullInterval(bounds, ray); }

  /// The triangle in leaf slot s.
  Triangle leaf_triangle(size_t s) const {
    return leaf_blocks[s / kTriangleBlockWidth].get(int(s % kTriangleBlockWidth));
  }
  /// Box of a reference (a node: union of its children; a leaf: union of its triangles'
  /// full boxes, which with split_references may exceed the leaf's own child box).
  Bounds3 ref_bounds(uint32_t ref) const;
  /// Checks the invariants: every triangle id in [0, triangle_count) exactly once (at least
  /// once with split_references), no leaf slot shared, leaf triangles inside their child box
  /// (overlapping it with split_references), child boxes containing their subtree, no empty
  /// leaf or node, every node reachable exactly once. "" when all hold, else the first violation.
  std::string validate(size_t triangle_count) const;
  /// Wide nodes on the longest root-to-leaf path (a root with only leaf children is 1).
  int depth() const { return depth_; }
  /// Bytes of nodes, prim_ids and leaf_blocks (their sizes: reserved, never touched
  /// capacity does not count).
  size_t memory_bytes() const {
    return nodes.size() * sizeof(WideNode) + prim_ids.size() * sizeof(uint32_t) +
           leaf_blocks.size() * sizeof(TriangleBlock);
  }

 private:
  // The traversals; Finite: the ray's origin and inverse direction are finite, so no slab
  // distance is NaN and the box test may combine axes in any order (same result, shorter chain).
  template <bool CaptureStats, bool Finite>
  Hit intersect_impl(const Ray& ray, const RayPrecomp& rp, std::span<const uint32_t> start, TraceStats* stats) const;
  template <bool CaptureStats, bool Finite>
  bool occluded_impl(const Ray& ray, const RayPrecomp& rp, std::span<const uint32_t> start, TraceStats* stats) const;
  int depth_ = 0;
};

}  // namespace rayscout
