// GroupListBuilder (private): Algorithm 1 of Hendrich et al. 2019 (candidate lists), k-ary,
// for one shaft or for a group of shafts of one voxel in one tree walk, and the overflow policy
// around it.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <span>
#include <vector>

#include "rayscout/shafts/tree_view.h"
#include "shaft.h"

namespace rayscout::detail {

/// Sample rays of shafts with their real closest-hit distances (occlusion counts), as
/// structure of arrays so that the box test over all of them vectorises.
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

/// The sample rays of `per` that must enter a box for hitProbability >= min_prob: the least
/// count with count / per >= min_prob, or per + 1 (none can) when min_prob > 1. Algorithm 1
/// depends on min_prob only through it.
inline int required_hits(double min_prob, int per) {
  int need = 0;
  while (need < per && double(need) / double(per) < min_prob) ++need;
  if (per > 0 && double(need) / double(per) < min_prob) need = per + 1;
  return need;
}

/// cullNodeSubtree's answer when no descendant overlaps the shaft.
inline constexpr uint32_t kNoNode = 0xFFFFFFFFu;

/// Grows a voxel by a margin far above the rounding of sample origins: a node box that
/// contains it overlaps every shaft of the voxel, and every sample ray starts inside it
/// (hit probability exactly 1).
inline Bounds3 voxel_margin_box(const Bounds3& v) {
  const Vec3 m = v.diagonal() * (1.0f / 1024.0f) + max(abs(v.lo), abs(v.hi)) * (1.0f / 1048576.0f);
  return Bounds3{v.lo - m, v.hi + m};
}

/// Candidate lists of up to 64 shafts of one voxel whose cells lie in one rectangle of a cube
/// face (the group cone `group`, which contains every member's cone); a single shaft is a
/// group of one (the budget pilots). A DFS over the tree carries the set of members for which
/// a node is still open; each member sees exactly the nodes, tests and order its own
/// Algorithm 1 would (tests/shafts/group_list_builder_test.cpp checks this against a literal
/// transcription), provided every member orders children the same way (Bvh2: the members'
/// centre directions agree on which components are > 0; a k-ary tree is ordered by the group
/// cone's centre direction, which may order a member's list differently). What is shared:
/// the walk down to the voxel's ancestors, one node load per visit, one group overlap test
/// that rejects a node for all members at once, and the hit probability of all members as one
/// vectorised loop over their sample rays.
class GroupListBuilder {
 public:
  static constexpr int kMaxGroup = 64;

  /// DFS stack of (node, member mask); push stays inline (vector::push_back was not).
  class Stack {
   public:
    void clear() { n_ = 0; }
    bool empty() const { return n_ == 0; }
    void push(uint32_t node, uint64_t mask) {
      if (n_ == buf_.size()) buf_.resize(buf_.empty() ? 256 : 2 * buf_.size());
      buf_[n_++] = {node, mask};
    }
    std::pair<uint32_t, uint64_t> pop() { return buf_[--n_]; }

   private:
    std::vector<std::pair<uint32_t, uint64_t>> buf_;
    size_t n_ = 0;
  };
  /// Working memory of a builder; one per task range, reused across its groups (a fresh
  /// builder per group spent measurable time in allocations).
  struct Scratch {
    std::vector<int32_t> hit;    ///< per sample ray: enters the current box before its hit
    Stack stack, cull_stack;     ///< Algorithm 1's DFS; cullNodeSubtree's descent
    std::vector<uint64_t> over;  ///< per child of the node being culled: members it overlaps
    std::vector<uint32_t> order; ///< children sorted far first
  };

  /// members[i] uses samples [i s, (i + 1) s) of `samples`, s = samples_per_shaft. Only the
  /// group shaft must be placed in the voxel: members are used for their cones only (their
  /// tests take the group's box difference), so shafts of any voxel may stand for them.
  /// scratch (borrowed, may be shared by consecutive builders of one thread) holds the stacks.
  GroupListBuilder(const TreeView& tree, const Shaft& group, std::span<const Shaft* const> members,
                   const ShaftSamples& samples, int samples_per_shaft, Scratch& scratch)
      : tree_(tree), group_(group), members_(members), samples_(samples), per_(samples_per_shaft), scratch_(scratch) {
    grown_voxel_ = voxel_margin_box(group.voxel());
    scratch_.hit.resize(samples.size());
  }
  /// The same with its own scratch.
  GroupListBuilder(const TreeView& tree, const Shaft& group, std::span<const Shaft* const> members,
                   const ShaftSamples& samples, int samples_per_shaft)
      : GroupListBuilder(tree, group, members, samples, samples_per_shaft, own_) {}
  // scratch_ may point at own_: a copy would share the source's scratch.
  GroupListBuilder(const GroupListBuilder&) = delete;
  GroupListBuilder& operator=(const GroupListBuilder&) = delete;

  /// Algorithm 1 with threshold min_prob for every member in `active`; lists[i] receives
  /// member i's node indices near first. Returns the members whose list fit in max_len (the
  /// others' lists are incomplete and must be rebuilt with a raised threshold).
  uint64_t build(double min_prob, int max_len, uint64_t active, std::vector<uint32_t>* lists) {
    for (uint64_t m = active; m; m &= m - 1) lists[std::countr_zero(m)].clear();
    // count / per >= min_prob as an integer count (same decision, no division per member).
    need_ = required_hits(min_prob, per_);
    uint64_t live = active;
    auto& stack = scratch_.stack;
    stack.clear();
    stack.push(tree_.root, active);  // line 1
    const bool shortcut = need_ <= per_;  // min_prob <= 1
    while (!stack.empty()) {
      const auto [node, mask_in] = stack.pop();
      const uint64_t mask = mask_in & live;
      if (!mask) continue;
      const Bounds3& box = tree_.bounds[node];
      const bool leaf = tree_.is_leaf(node);
      // An ancestor of the voxel passes lines 5 and 8 for certain (voxel_margin_box).
      if (shortcut && !leaf && box.contains(grown_voxel_)) {
        push_children_far_first(node, mask);
        continue;
      }
      if (box.empty()) continue;
      // Members and group share the voxel, hence the box difference.
      const Shaft::BoxDiff diff = group_.diff(box);
      if (std::popcount(mask) > 1 && !group_.overlaps(diff)) continue;
      uint64_t stop;  // members for which the node ends here: lines 16-18 (inner) or 20 (leaf)
      if (leaf) {
        stop = overlapping(diff, mask);  // line 5
      } else if (need_ > 0) {
        // A member whose sample rays enter the box (at least one does) overlaps it for
        // certain: the padded shaft holds every point within far more than the slab test's
        // rounding of a sample ray, and the float overlap test keeps every box the exact test
        // keeps. So only the others take the overlap test; same decisions as Algorithm 1.
        const uint64_t open = expanding(box, mask);  // lines 7-8
        stop = overlapping(diff, mask & ~open);      // line 5
        if (open) push_children_far_first(node, open);
      } else {
        const uint64_t over = overlapping(diff, mask);  // line 5
        const uint64_t open = expanding(box, over);     // lines 7-8
        stop = over & ~open;
        if (open) push_children_far_first(node, open);
      }
      if (!stop) continue;
      if (!leaf) cull_subtrees(node, stop);  // line 16
      for (uint64_t m = stop; m; m &= m - 1) {
        const int i = std::countr_zero(m);
        const uint32_t entry = leaf ? node : culled_[i];
        if (entry == kNoNode) continue;  // line 17
        lists[i].push_back(entry);       // lines 18, 20
        if (int(lists[i].size()) > max_len) live &= ~(uint64_t(1) << i);
      }
    }
    return live;
  }

  /// The list of each member in `members` whose list still overflows after retry_overflow:
  /// the single node cullNodeSubtree(root), or nothing when the shaft reaches no geometry.
  /// One member at a time, so each takes its own overlap tests, as its own shaft would.
  void fallback(uint64_t members, std::vector<uint32_t>* lists) {
    for (uint64_t f = members; f; f &= f - 1) {
      const int i = std::countr_zero(f);
      cull_subtrees(tree_.root, uint64_t(1) << i);
      lists[i].clear();
      if (culled_[i] != kNoNode) lists[i].push_back(culled_[i]);
    }
  }

 private:
  /// Members in mask whose shaft overlaps the box with difference d. (One member at a time:
  /// measured faster than one loop over all members' axes, whose per-member reduction costs
  /// more than it saves.)
  uint64_t overlapping(const Shaft::BoxDiff& d, uint64_t mask) const {
    uint64_t over = 0;
    for (uint64_t r = mask; r; r &= r - 1) {
      const int i = std::countr_zero(r);
      if (members_[size_t(i)]->overlaps(d)) over |= uint64_t(1) << i;
    }
    return over;
  }

  /// cullNodeSubtree(node) for every member in mask, into culled_: descend while exactly one
  /// child overlaps the member's shaft; that descendant, or kNoNode when no child overlaps (a
  /// leaf is its own answer). A child's box difference is computed once for all members.
  void cull_subtrees(uint32_t node, uint64_t mask) {
    auto& cull_stack = scratch_.cull_stack;
    cull_stack.clear();
    cull_stack.push(node, mask);
    while (!cull_stack.empty()) {
      const auto [n, m] = cull_stack.pop();
      if (tree_.is_leaf(n)) {
        for (uint64_t r = m; r; r &= r - 1) culled_[std::countr_zero(r)] = n;
        continue;
      }
      const auto kids = tree_.children(n);
      const size_t nkids = kids.size();
      uint64_t once = 0, twice = 0;  // members with >= 1 / >= 2 overlapping children
      scratch_.over.resize(nkids);
      uint64_t* over = scratch_.over.data();
      for (size_t c = 0; c < nkids; ++c) {
        const Bounds3& box = tree_.bounds[kids[c]];
        uint64_t o = 0;
        const uint64_t open = m & ~twice;
        if (!box.empty() && open) {
          const Shaft::BoxDiff diff = group_.diff(box);
          if (std::popcount(open) == 1 || group_.overlaps(diff)) o = overlapping(diff, open);
        }
        over[c] = o;
        twice |= once & o;
        once |= o;
      }
      for (uint64_t r = twice; r; r &= r - 1) culled_[std::countr_zero(r)] = n;
      for (uint64_t r = m & ~once; r; r &= r - 1) culled_[std::countr_zero(r)] = kNoNode;
      for (size_t c = 0; c < nkids; ++c)
        if (const uint64_t single = over[c] & ~twice) cull_stack.push(kids[c], single);
    }
  }

  /// Members in `mask` whose hit probability of box is >= min_prob (getHitProbability: the
  /// fraction of a member's sample rays that enter the box before their hit), evaluated for
  /// all sample rays in one loop.
  uint64_t expanding(const Bounds3& b, uint64_t mask) {
    const float* __restrict ox = samples_.ox.data(); const float* __restrict oy = samples_.oy.data();
    const float* __restrict oz = samples_.oz.data(); const float* __restrict ix = samples_.ix.data();
    const float* __restrict iy = samples_.iy.data(); const float* __restrict iz = samples_.iz.data();
    const float* __restrict ht = samples_.hit_t.data();
    // All members' sample rays in one vectorised loop (members outside `mask` are computed
    // too: cheaper than a gather), then a count per member.
    const size_t n = samples_.size();
    int32_t* __restrict hit = scratch_.hit.data();
    for (size_t i = 0; i < n; ++i) hit[i] = sample_enters(b, ox[i], oy[i], oz[i], ix[i], iy[i], iz[i], ht[i]);
    uint64_t open = 0;
    for (uint64_t m = mask; m; m &= m - 1) {
      const int s = std::countr_zero(m);
      const int32_t* h = hit + size_t(s) * size_t(per_);
      int count = 0;
      for (int k = 0; k < per_; ++k) count += h[k];
      if (count >= need_) open |= uint64_t(1) << s;
    }
    return open;
  }

  /// Lines 9-14: the children go on the stack so that the nearest along the shaft's centre
  /// direction is popped first (Bvh2: by the split axis; k-ary: by box centre). The paper's
  /// lines pop the far one first and its traversal pushes the list, popping the near entry
  /// first; ours keeps the list near first and seeds in list order: same entry order.
  void push_children_far_first(uint32_t node, uint64_t mask) {
    const auto kids = tree_.children(node);
    const Vec3& dir = group_.center_dir();
    if (tree_.split_axis[node] >= 0 && kids.size() == 2) {
      // Members agree on the sign of every centre component (the caller groups them so).
      const bool left_near = members_[0]->center_dir()[tree_.split_axis[node]] > 0.0f;
      scratch_.stack.push(left_near ? kids[1] : kids[0], mask);
      scratch_.stack.push(left_near ? kids[0] : kids[1], mask);
      return;
    }
    auto& order = scratch_.order;
    order.assign(kids.begin(), kids.end());
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
      const float da = dot(tree_.bounds[a].center(), dir), db = dot(tree_.bounds[b].center(), dir);
      return da > db || (da == db && a > b);  // farthest first on the stack
    });
    for (uint32_t c : order) scratch_.stack.push(c, mask);
  }

  const TreeView& tree_;
  const Shaft& group_;
  std::span<const Shaft* const> members_;
  const ShaftSamples& samples_;
  int per_;
  int need_ = 0;  ///< sample rays that must enter a box for its node to be expanded
  Scratch own_;
  Scratch& scratch_;
  uint32_t culled_[kMaxGroup];
  Bounds3 grown_voxel_;  ///< the voxel grown by voxel_margin_box
};

/// Distance, in voxel diagonals, of the first clamp of the overflow policy. Starting at 8
/// gives the same steps saved on the bench scenes (docs/history/shafts.md, session 29).
inline constexpr float kFirstReach = 4.0f;

/// What a list build does on overflow, for one shaft (budget pilots) and for a group (the
/// build) alike: first near_retries rebuilds at min_prob with the sample rays' hit distances
/// clamped to kFirstReach voxel diagonals, then half that, and so on (ShaftConfig::
/// near_retries, ours); then raised thresholds min_prob + (i+1)/20 for i < retries, distances
/// still clamped (sec. 4.3 only says "raised gradually"; the step is the reference
/// implementation's), skipping a threshold whose required_hits for `per` samples per shaft
/// equals the previous build's (the same lists again: with 3 samples and min_prob 7/8, only
/// 1.025 of 0.925, 0.975, ..., 1.375 changes anything). `clamp(reach)` clamps the distances;
/// `rebuild(min_prob, clamped)` rebuilds the lists that overflowed and returns whether all fit
/// now (clamped: a rebuild of the first kind). Returns whether all fit (else the caller falls
/// back to cullNodeSubtree(root), GroupListBuilder::fallback).
template <class Rebuild, class Clamp>
bool retry_overflow(int near_retries, int retries, double min_prob, int per, float voxel_diagonal, Rebuild rebuild,
                    Clamp clamp) {
  float reach = kFirstReach * voxel_diagonal;
  for (int i = 0; i < near_retries; ++i, reach *= 0.5f) {
    clamp(reach);
    if (rebuild(min_prob, true)) return true;
  }
  for (int i = 0, need = required_hits(min_prob, per); i < retries; ++i) {
    const double p = min_prob + double(i + 1) / 20.0;
    const int raised = required_hits(p, per);
    if (raised == need) continue;  // the same lists again
    need = raised;
    if (rebuild(p, false)) return true;
  }
  return false;
}

}  // namespace rayscout::detail
