// GroupListBuilder: one tree walk for a group of shafts gives each member the list its own
// Algorithm 1 gives (Bvh2), including cullNodeSubtree entries and overflowing members; a
// group of one (the budget pilots) gives that list too.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "generated_scenes.h"
#include "group_list_builder.h"
#include "rayscout/bvh/bvh2.h"

namespace rayscout {
namespace {

/// Algorithm 1 of Hendrich et al. 2019 for one shaft, transcribed line by line (k-ary: children
/// ordered by the split axis for Bvh2, else by box centre along the shaft's centre direction),
/// with the one shortcut the builder takes too: a node whose box contains the voxel (grown by
/// voxel_margin_box) passes lines 5 and 8 for certain, and lines 9-14 popping the near child
/// first (the paper pops the far one and reverses the list when seeding; docs/shafts.md). The
/// reference GroupListBuilder must match.
class Algorithm1 {
 public:
  Algorithm1(const TreeView& tree, const Shaft& shaft, const detail::ShaftSamples& samples)
      : tree_(tree), shaft_(shaft), samples_(samples), inner_(detail::voxel_margin_box(shaft.voxel())) {}

  /// Fills out with node indices, near first; false (out incomplete) once longer than max_len.
  bool build(double min_prob, int max_len, std::vector<uint32_t>& out) const {
    out.clear();
    std::vector<uint32_t> stack{tree_.root};  // line 1
    while (!stack.empty()) {                   // line 2
      uint32_t node = stack.back();            // lines 3-4
      stack.pop_back();
      if (min_prob <= 1.0 && !tree_.is_leaf(node) && tree_.bounds[node].contains(inner_)) {
        push_children_far_first(node, stack);
        continue;
      }
      if (!shaft_.overlaps(tree_.bounds[node])) continue;  // line 5
      if (!tree_.is_leaf(node)) {                          // line 6
        if (hit_probability(node) >= min_prob) {           // lines 7-8
          push_children_far_first(node, stack);            // lines 9-14
          continue;
        }
        node = cull_subtree(node);     // line 16
        if (node == detail::kNoNode) continue;  // line 17
      }
      out.push_back(node);  // lines 18, 20
      if (int(out.size()) > max_len) return false;
    }
    return true;
  }

  /// cullNodeSubtree: descend while exactly one child overlaps the shaft.
  uint32_t cull_subtree(uint32_t node) const {
    for (;;) {
      if (tree_.is_leaf(node)) return node;
      uint32_t only = detail::kNoNode;
      int overlapping = 0;
      for (uint32_t c : tree_.children(node))
        if (shaft_.overlaps(tree_.bounds[c])) {
          only = c;
          if (++overlapping > 1) return node;
        }
      if (overlapping == 0) return detail::kNoNode;
      node = only;
    }
  }

 private:
  /// getHitProbability: the fraction of sample rays that enter the node's box before their hit.
  double hit_probability(uint32_t node) const {
    int hits = 0;
    for (size_t i = 0; i < samples_.size(); ++i)
      hits += detail::sample_enters(tree_.bounds[node], samples_.ox[i], samples_.oy[i], samples_.oz[i], samples_.ix[i],
                                    samples_.iy[i], samples_.iz[i], samples_.hit_t[i]);
    return double(hits) / double(samples_.size());
  }

  void push_children_far_first(uint32_t node, std::vector<uint32_t>& stack) const {
    const auto kids = tree_.children(node);
    const Vec3& dir = shaft_.center_dir();
    if (tree_.split_axis[node] >= 0 && kids.size() == 2) {
      const bool left_near = dir[tree_.split_axis[node]] > 0.0f;  // line 9
      stack.push_back(left_near ? kids[1] : kids[0]);
      stack.push_back(left_near ? kids[0] : kids[1]);
      return;
    }
    std::vector<uint32_t> order(kids.begin(), kids.end());
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
      const float da = dot(tree_.bounds[a].center(), dir), db = dot(tree_.bounds[b].center(), dir);
      return da > db || (da == db && a > b);  // farthest first on the stack
    });
    stack.insert(stack.end(), order.begin(), order.end());
  }

  const TreeView& tree_;
  const Shaft& shaft_;
  const detail::ShaftSamples& samples_;
  Bounds3 inner_;
};

TEST(GroupListBuilder, MembersGetTheirOwnAlgorithm1Lists) {
  const std::vector<Triangle> tris = testing::random_soup(2000, 5);
  const Bvh2 bvh = Bvh2::build(tris);
  const TreeView tree = TreeView::from_bvh2(bvh);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  size_t compared = 0, entries = 0, overflowed = 0;
  for (int d : {4, 3}) {
    const ShaftGrid grid(tree.bounds[0], {6, 5, 4}, d);
    for (int trial = 0; trial < 60; ++trial) {
      const uint32_t voxel = uint32_t(rng() % grid.voxel_count());
      const int face = int(rng() % 6);
      // Cells of one face quadrant whose centre directions agree in sign (as the build groups them).
      std::vector<Shaft> members;
      const bool upper_u = rng() % 2, upper_v = rng() % 2;
      const int half = d / 2;
      const int u0 = upper_u ? half : 0, u1 = upper_u ? d : half, v0 = upper_v ? half : 0, v1 = upper_v ? d : half;
      for (int v = v0; v < v1; ++v)
        for (int u = u0; u < u1; ++u) members.emplace_back(grid, ShaftCoord{voxel, uint32_t((face * d + v) * d + u)});
      // d = 3: the middle row's centre component may be +-0; keep only sign-agreeing members.
      const Vec3 c0 = members[0].center_dir();
      std::erase_if(members, [&](const Shaft& s) {
        for (int k = 0; k < 3; ++k)
          if ((s.center_dir()[k] > 0.0f) != (c0[k] > 0.0f)) return true;
        return false;
      });
      const auto lo = grid.cell_range(uint32_t((face * d + v0) * d + u0));
      const auto hi = grid.cell_range(uint32_t((face * d + v1 - 1) * d + u1 - 1));
      const Shaft group(grid, voxel, ShaftGrid::CellRange{lo.axis, lo.sign, lo.u0, hi.u1, lo.v0, hi.v1});
      const int per = 6;
      detail::ShaftSamples samples;
      samples.resize(members.size() * per);
      for (size_t m = 0; m < members.size(); ++m)
        for (int k = 0; k < per; ++k) {
          float rnd[5];
          for (float& r : rnd) r = u01(rng);
          const Ray ray = members[m].sample_ray(rnd);
          const size_t i = m * per + size_t(k);
          samples.ox[i] = ray.org.x; samples.oy[i] = ray.org.y; samples.oz[i] = ray.org.z;
          samples.ix[i] = 1.0f / ray.dir.x; samples.iy[i] = 1.0f / ray.dir.y; samples.iz[i] = 1.0f / ray.dir.z;
          samples.hit_t[i] = bvh.intersect<false>(ray, {}, nullptr).t;
        }
      const int max_len = trial % 3 == 0 ? 3 : 31;  // small limit: some members overflow
      const double min_prob = trial % 2 ? 0.5 : 0.3;
      std::vector<std::vector<uint32_t>> lists(members.size());
      std::vector<const Shaft*> member_ptrs;
      for (const Shaft& m : members) member_ptrs.push_back(&m);
      detail::GroupListBuilder gb(tree, group, member_ptrs, samples, per);
      const uint64_t ok = gb.build(min_prob, max_len, (uint64_t(1) << members.size()) - 1, lists.data());
      for (size_t m = 0; m < members.size(); ++m) {
        detail::ShaftSamples one;
        one.resize(per);
        for (int k = 0; k < per; ++k) {
          const size_t i = m * per + size_t(k);
          one.ox[k] = samples.ox[i]; one.oy[k] = samples.oy[i]; one.oz[k] = samples.oz[i];
          one.ix[k] = samples.ix[i]; one.iy[k] = samples.iy[i]; one.iz[k] = samples.iz[i];
          one.hit_t[k] = samples.hit_t[i];
        }
        const Algorithm1 reference(tree, members[m], one);
        std::vector<uint32_t> ref;
        const bool fits = reference.build(min_prob, max_len, ref);
        // A group of one, placed in the voxel (what the budget pilots build).
        const Shaft* const alone_ptr = &members[m];
        detail::GroupListBuilder alone(tree, members[m], {&alone_ptr, 1}, one, per);
        std::vector<uint32_t> alone_list;
        ASSERT_EQ(fits, alone.build(min_prob, max_len, 1, &alone_list) == 1) << "d " << d << " trial " << trial;
        ASSERT_EQ(fits, bool(ok >> m & 1)) << "d " << d << " trial " << trial << " member " << m;
        if (!fits) {
          ++overflowed;
          // The fallback of an overflowing member: cullNodeSubtree(root), alone or in the group.
          const uint32_t root_cull = reference.cull_subtree(tree.root);
          const std::vector<uint32_t> want =
              root_cull == detail::kNoNode ? std::vector<uint32_t>{} : std::vector<uint32_t>{root_cull};
          gb.fallback(uint64_t(1) << m, lists.data());
          alone.fallback(1, &alone_list);
          EXPECT_EQ(want, lists[m]) << "d " << d << " trial " << trial << " member " << m;
          EXPECT_EQ(want, alone_list) << "d " << d << " trial " << trial << " member " << m;
          continue;
        }
        EXPECT_EQ(ref, lists[m]) << "d " << d << " trial " << trial << " member " << m;
        EXPECT_EQ(ref, alone_list) << "d " << d << " trial " << trial << " member " << m;
        ++compared;
        entries += ref.size();
      }
    }
  }
  EXPECT_GT(compared, 100u);
  EXPECT_GT(entries, 3 * compared);
  EXPECT_GT(overflowed, 5u);
}

// retry_overflow: clamps at 4, 2, 1, 1/2, ... voxel diagonals at min_prob, then Algorithm 1's
// thresholds min_prob + (i+1)/20, stopping at the first rebuild that fits.
TEST(OverflowPolicy, ClampsNearFirstThenRaisesTheThreshold) {
  struct Call { double min_prob; bool clamped; float reach; };
  auto run = [](int near_retries, int retries, int fits_at, std::vector<Call>& calls) {
    calls.clear();
    float reach = -1.0f;
    return detail::retry_overflow(
        near_retries, retries, 0.5, 20, 2.0f,
        [&](double p, bool clamped) {
          calls.push_back({p, clamped, reach});
          return int(calls.size()) == fits_at;
        },
        [&](float r) { reach = r; });
  };
  std::vector<Call> calls;
  EXPECT_FALSE(run(3, 2, 0, calls));
  ASSERT_EQ(calls.size(), 5u);
  const float reaches[] = {8.0f, 4.0f, 2.0f};
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(calls[i].min_prob, 0.5);
    EXPECT_TRUE(calls[i].clamped);
    EXPECT_EQ(calls[i].reach, reaches[i]);
  }
  EXPECT_DOUBLE_EQ(calls[3].min_prob, 0.55);
  EXPECT_DOUBLE_EQ(calls[4].min_prob, 0.6);
  EXPECT_FALSE(calls[3].clamped || calls[4].clamped);
  EXPECT_EQ(calls[4].reach, 2.0f) << "the raised thresholds keep the last clamp";
  EXPECT_TRUE(run(3, 2, 2, calls));
  EXPECT_EQ(calls.size(), 2u) << "stops at the first rebuild that fits";
  EXPECT_TRUE(run(0, 10, 1, calls));
  EXPECT_FALSE(calls[0].clamped);
  EXPECT_EQ(calls[0].reach, -1.0f) << "near_retries = 0: raised thresholds only, no clamp";
  EXPECT_DOUBLE_EQ(calls[0].min_prob, 0.55);
}

// A raised threshold that asks as many sample rays to enter a box as the previous build did
// gives the same lists: retry_overflow skips it. The defaults: shafts-wide (3 samples, min_prob
// 7/8) rebuilds only at 1.025 (not at 0.925, 0.975, 1.075, ...), shafts (4, 1/2) at 0.55 and 0.8.
TEST(OverflowPolicy, SkipsThresholdsThatCannotChangeTheList) {
  auto raised = [](double min_prob, int per, int near_retries) {
    std::vector<double> calls;
    EXPECT_FALSE(detail::retry_overflow(
        near_retries, 10, min_prob, per, 1.0f,
        [&](double p, bool clamped) {
          if (!clamped) calls.push_back(p);
          return false;
        },
        [](float) {}));
    return calls;
  };
  for (const int near_retries : {0, 5}) {
    const auto wide = raised(7.0 / 8.0, 3, near_retries);
    ASSERT_EQ(wide.size(), 1u);
    EXPECT_DOUBLE_EQ(wide[0], 7.0 / 8.0 + 0.15);
    const auto binary = raised(0.5, 4, near_retries);
    ASSERT_EQ(binary.size(), 2u);
    EXPECT_DOUBLE_EQ(binary[0], 0.55);
    EXPECT_DOUBLE_EQ(binary[1], 0.8);
  }
  EXPECT_EQ(detail::required_hits(0.875, 3), 3);
  EXPECT_EQ(detail::required_hits(1.025, 3), 4);
  EXPECT_EQ(detail::required_hits(0.0, 3), 0);
  EXPECT_EQ(raised(0.5, 20, 0).size(), 10u) << "20 samples: every step of 1/20 asks one more";
}

// A clamp lets a sample ray count as hitting at the reach at the latest.
TEST(OverflowPolicy, ClampShortensOnlyLongerHits) {
  detail::ShaftSamples s;
  s.resize(3);
  s.hit_t = {1.0f, 5.0f, kInfinity};
  s.clamp_hits(2.0f);
  EXPECT_EQ(s.hit_t, (std::vector<float>{1.0f, 2.0f, 2.0f}));
}

}  // namespace
}  // namespace rayscout
