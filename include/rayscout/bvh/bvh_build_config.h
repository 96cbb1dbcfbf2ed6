// BvhBuildConfig: the tunables of the binned SAH builder and of its 8-wide collapse.
#pragma once

namespace rayscout {

/// Most bins per axis (BvhBuildConfig::bins): the builder's bin arrays are sized for it.
inline constexpr int kBvhMaxBins = 256;
/// Most triangles in one leaf (max_leaf_size, collapse_max_leaf, and leaf_block, which a
/// larger value could never fill): a WideRef holds a leaf's count in 4 bits.
inline constexpr int kBvhMaxLeafSize = 15;
/// Most references one triangle may be pre-split into (presplit_max_pieces): itself and up
/// to 64 more.
inline constexpr int kBvhMaxPresplitPieces = 65;

/// How WideBvh::from_bvh2 turns the binary tree into 8-wide nodes.
enum class CollapseMethod {
  /// Each wide node opens its largest-area inner child until it has 8 children; Bvh2 leaves
  /// stay leaves (Wald et al. 2008, Embree's BVH8).
  Greedy,
  /// Dynamic programming over the Bvh2 minimising the wide tree's SAH cost (Ylitie, Karras,
  /// Laine, HPG 2017, sec. 4.1): every subtree is either one leaf, one wide node, or spread
  /// over several child slots of its wide ancestor.
  Sah,
};

/// Tunables of the binned SAH builder (Wald, "On fast construction of SAH-based bounding
/// volume hierarchies", RT 2007). Costs are relative; only their ratio matters.
struct BvhBuildConfig {
  /// Bins per axis over the centroid bounds (Wald 2007 sec. 3.1), 2..kBvhMaxBins. More bins:
  /// better splits, slower build; 32 is the usual sweet spot.
  int bins = 32;
  /// A node with at most this many triangles becomes a leaf when its SAH leaf cost is not
  /// higher than the best split's cost; larger nodes are always split. At most
  /// kBvhMaxLeafSize.
  int max_leaf_size = 4;
  /// Cost of visiting one node relative to one ray-triangle test (C_T in the SAH
  /// C = C_T + C_I (A_L N_L + A_R N_R) / A).
  float traversal_cost = 1.0f;
  /// Cost of one ray-triangle test (C_I in the SAH).
  float intersection_cost = 1.0f;
  /// Triangles tested together in a leaf: the SAH leaf cost charges ceil(n / leaf_block)
  /// tests. 1 for scalar leaf tests (Bvh2); the wide BVH tests blocks of 4 triangles.
  int leaf_block = 1;
  /// Extra references for pre-splitting large triangles, as a fraction of the triangle count
  /// (Karras and Aila, HPG 2013, sec. 3; they use 0.3). 0 = off: every triangle in exactly
  /// one leaf. On: a triangle may sit in several leaves, each with a tight box of its part.
  float presplit = 0.0f;
  /// Most references one triangle may be pre-split into (1..kBvhMaxPresplitPieces). 2 (one
  /// split, at the coarsest grid plane crossing it) spreads the budget over many triangles;
  /// up to 65 pieces per triangle cut scene-spanning triangles such as Conference's floor
  /// into many references and cost up to 20 % of closest-hit throughput there.
  int presplit_max_pieces = 2;
  /// Nodes with at least this many triangles bin in parallel and recurse as parallel tasks;
  /// below it the subtree is built serially (the result does not depend on it).
  int parallel_threshold = 4096;
  /// Collapse of the Bvh2 into the 8-wide tree (WideBvh only).
  CollapseMethod collapse = CollapseMethod::Greedy;
  /// SAH collapse: cost of visiting one wide node (testing its 8 child boxes, ordering them),
  /// relative to one 4-triangle block test. 1.5 measured best of 1 / 1.5 / 2 (2 cost
  /// Conference 15 % of its primary-ray throughput).
  float collapse_node_cost = 1.5f;
  /// SAH collapse: fixed cost of entering one leaf (the stack pop and leaf setup).
  float collapse_leaf_cost = 0.3f;
  /// SAH collapse: cost of one 4-triangle block test in a leaf.
  float collapse_block_cost = 1.0f;
  /// SAH collapse: most references (pre-split pieces counted apart) a merged leaf may hold
  /// (1..kBvhMaxLeafSize; Bvh2 leaves larger than this stay as they are).
  int collapse_max_leaf = 8;
};

}  // namespace rayscout
