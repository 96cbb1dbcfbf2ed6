// Candidate list of one shaft: Algorithm 1 of Hendrich et al. 2019 generalised to k-ary trees.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "rayscout/core/triangle.h"
#include "shaft.h"
#include "rayscout/shafts/tree_view.h"

namespace rayscout::detail {

/// Sample rays of one shaft with their real closest-hit distances (occlusion counts), as
/// structure of arrays so the 20-ray box test vectorises.
struct ShaftSamples {
  std::vector<float> ox, oy, oz, ix, iy, iz, hit_t;
  void resize(size_t n) {
    for (auto* v : {&ox, &oy, &oz, &ix, &iy, &iz, &hit_t}) v->resize(n);
  }
  size_t size() const { return hit_t.size(); }
  /// Lets every ray count as hitting at reach at the latest (retry_overflow's clamp).
  void clamp_hits(float reach) {
    for (float& t : hit_t) t = std::min(t, reach);
  }
};

/// 1 when a sample ray (origin o, inverse direction i, real hit at hit_t) enters box b before
/// its hit, else 0: a plain slab test, for hitProbability, an estimate rather than a culling
/// decision. Branch-free, so loops over many sample rays vectorise.
inline int sample_enters(const Bounds3& b, float ox, float oy, float oz, float ix, float iy, float iz, float hit_t) {
  const float x0 = (b.lo.x - ox) * ix, x1 = (b.hi.x - ox) * ix;
  const float y0 = (b.lo.y - oy) * iy, y1 = (b.hi.y - oy) * iy;
  const float z0 = (b.lo.z - oz) * iz, z1 = (b.hi.z - oz) * iz;
  const float tn = std::max(std::max(std::min(x0, x1), std::min(y0, y1)), std::max(std::min(z0, z1), 0.0f));
  const float tf = std::min(std::min(std::max(x0, x1), std::max(y0, y1)), std::min(std::max(z0, z1), hit_t));
  return tn <= tf ? 1 : 0;
}

inline constexpr uint32_t kNoNode = 0xFFFFFFFFu;

/// Distance, in voxel diagonals, of the first clamp of the overflow policy. Starting at 8
/// gives the same steps saved on the bench scenes (docs/history/shafts.md, session 29).
inline constexpr float kFirstReach = 4.0f;

/// What a list build does on overflow, for one shaft (budget pilots) and for a group (the
/// build) alike: first near_retries rebuilds at min_prob with the sample rays' hit distances
/// clamped to kFirstReach voxel diagonals, then half that, and so on (ShaftConfig::
/// near_retries, ours); then Algorithm 1's thresholds min_prob + (i+1)/20 for i < retries,
/// distances still clamped. `clamp(reach)` clamps the distances; `rebuild(min_prob, clamped)`
/// rebuilds the lists that overflowed and returns whether all fit now (clamped: a rebuild of
/// the first kind). Returns whether all fit (else the caller falls back to cullNodeSubtree(root)).
template <class Rebuild, class Clamp>
bool retry_overflow(int near_retries, int retries, double min_prob, float voxel_diagonal, Rebuild rebuild,
                    Clamp clamp) {
  float reach = kFirstReach * voxel_diagonal;
  for (int i = 0; i < near_retries; ++i, reach *= 0.5f) {
    clamp(reach);
    if (rebuild(min_prob, true)) return true;
  }
  for (int i = 0; i < retries; ++i)
    if (rebuild(min_prob + double(i + 1) / 20.0, false)) return true;
  return false;
}

/// cullNodeSubtree: descends while exactly one child overlaps the shaft; returns that
/// descendant, or kNoNode when no child overlaps (the subtree is unreachable).
inline uint32_t cull_subtree(const TreeView& tree, const Shaft& shaft, uint32_t node) {
  for (;;) {
    if (tree.is_leaf(node)) return node;
    uint32_t only = kNoNode;
    int overlapping = 0;
    for (uint32_t c : tree.children(node))
      if (shaft.overlaps(tree.bounds[c])) { only = c; if (++overlapping > 1) return node; }
    if (overlapping == 0) return kNoNode;
    node = only;
  }
}

/// The list of a shaft whose list still overflows after retry_overflow: the single node
/// cullNodeSubtree(root), or nothing when the shaft reaches no geometry.
inline void fallback_list(const TreeView& tree, const Shaft& shaft, std::vector<uint32_t>& list) {
  list.clear();
  if (const uint32_t n = cull_subtree(tree, shaft, tree.root); n != kNoNode) list.push_back(n);
}

/// Grows a voxel by a margin far above the rounding of sample origins: a node box that
/// contains it overlaps every shaft of the voxel, and every sample ray starts inside it
/// (hit probability exactly 1).
inline Bounds3 voxel_margin_box(const Bounds3& v) {
  const Vec3 m = v.diagonal() * (1.0f / 1024.0f) + max(abs(v.lo), abs(v.hi)) * (1.0f / 1048576.0f);
  return Bounds3{v.lo - m, v.hi + m};
}

/// Builds candidate lists of one shaft for a given threshold; scratch is reused.
class CandidateListBuilder {
 public:
  CandidateListBuilder(const TreeView& tree, const Shaft& shaft, const ShaftSamples& samples)
      : tree_(tree), shaft_(shaft), samples_(samples) {
    // A node whose box strictly contains the voxel (with a margin far above the rounding of
    // the sample origins) overlaps the shaft and every sample ray starts inside it, so its hit
    // probability is exactly 1: such ancestors of the voxel are expanded without the tests.
    inner_ = voxel_margin_box(shaft.voxel());
  }

  /// Fraction of sample rays that enter node's box before their hit (getHitProbability).
  /// A plain slab test: this is an estimate, not a culling decision.
  double hit_probability(uint32_t node) const {
    const size_t n = samples_.size();
    if (n == 0) return 1.0;
    const Bounds3& b = tree_.bounds[node];
    const float* ox = samples_.ox.data(); const float* oy = samples_.oy.data(); const float* oz = samples_.oz.data();
    const float* ix = samples_.ix.data(); const float* iy = samples_.iy.data(); const float* iz = samples_.iz.data();
    const float* ht = samples_.hit_t.data();
    int hits = 0;
    for (size_t i = 0; i < n; ++i) hits += sample_enters(b, ox[i], oy[i], oz[i], ix[i], iy[i], iz[i], ht[i]);
    return double(hits) / double(n);
  }

  /// cullNodeSubtree (see detail::cull_subtree).
  uint32_t cull_subtree(uint32_t node) const { return detail::cull_subtree(tree_, shaft_, node); }

  /// Algorithm 1 with threshold min_prob. Fills out (cleared first) with node indices, near
  /// first. Returns false (out then incomplete) as soon as the list exceeds max_len.
  bool build(double min_prob, int max_len, std::vector<uint32_t>& out) {
    out.clear();
    stack_.clear();
    stack_.push_back(tree_.root);
    while (!stack_.empty()) {
      uint32_t node = stack_.back();
      stack_.pop_back();
      if (min_prob <= 1.0 && !tree_.is_leaf(node) && contains_voxel(tree_.bounds[node])) {
        push_children_far_first(node);
        continue;
      }
      if (!shaft_.overlaps(tree_.bounds[node])) continue;
      if (!tree_.is_leaf(node)) {
        if (hit_probability(node) >= min_prob) {
          push_children_far_first(node);
          continue;
        }
        node = cull_subtree(node);
        if (node == kNoNode) continue;
      }
      out.push_back(node);
      if (int(out.size()) > max_len) return false;
    }
    return true;
  }

 private:
  bool contains_voxel(const Bounds3& b) const { return b.contains(inner_); }

  void push_children_far_first(uint32_t node) {
    const auto kids = tree_.children(node);
    const Vec3& dir = shaft_.center_dir();
    if (tree_.split_axis[node] >= 0 && kids.size() == 2) {
      const bool left_near = dir[tree_.split_axis[node]] > 0.0f;
      stack_.push_back(left_near ? kids[1] : kids[0]);
      stack_.push_back(left_near ? kids[0] : kids[1]);
      return;
    }
    order_.assign(kids.begin(), kids.end());
    std::sort(order_.begin(), order_.end(), [&](uint32_t a, uint32_t b) {
      const float da = dot(tree_.bounds[a].center(), dir), db = dot(tree_.bounds[b].center(), dir);
      return da > db || (da == db && a > b);  // farthest first on the stack
    });
    stack_.insert(stack_.end(), order_.begin(), order_.end());
  }

  const TreeView& tree_;
  const Shaft& shaft_;
  const ShaftSamples& samples_;
  std::vector<uint32_t> stack_, order_;
  Bounds3 inner_;  ///< the voxel grown by a margin (see the constructor)
};

}  // namespace rayscout::detail
