// Bvh2 and WideBvh construction: invariants on nasty and real meshes, corruption detection, determinism.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <string>

#include <tbb/global_control.h>

#include "generated_scenes.h"
#include "presplit.h"  // private: src/bvh
#include "rayscout/bvh/bvh2.h"
#include "rayscout/bvh/wide_bvh.h"
#include "rayscout/core/input_error.h"
#include "rayscout/core/scenes_dir.h"
#include "rayscout/scene/load_scene.h"

namespace rayscout {
namespace {

TEST(BvhBuild, NastyMeshesValidateForEveryLeafSizeAndBinCount) {
  for (const auto& m : testing::nasty_meshes()) {
    for (int leaf : {1, 4, 15}) {
      for (int bins : {2, 32}) {
        BvhBuildConfig c;
        c.max_leaf_size = leaf;
        c.bins = bins;
        c.parallel_threshold = 64;  // exercise the parallel paths on small meshes
        const Bvh2 bvh = Bvh2::build(m.triangles, c);
        EXPECT_EQ(bvh.validate(m.triangles), "") << m.name << " leaf " << leaf << " bins " << bins;
        const WideBvh wide = WideBvh::from_bvh2(bvh, m.triangles);
        EXPECT_EQ(wide.validate(m.triangles.size()), "") << m.name << " leaf " << leaf << " bins " << bins;
        for (const Bvh2Node& n : bvh.nodes) EXPECT_LE(n.count, leaf) << m.name;
        for (size_t i = 0; i < wide.prim_ids.size(); ++i) {
          if (wide.prim_ids[i] == kInvalidId) continue;  // block padding
          const Triangle t = wide.leaf_triangle(i);
          ASSERT_EQ(std::memcmp(&t, &m.triangles[wide.prim_ids[i]], sizeof(Triangle)), 0);
        }
      }
    }
  }
}

TEST(BvhBuild, PresplitReferencesValidate) {
  for (const auto& m : testing::nasty_meshes()) {
    BvhBuildConfig c;
    c.presplit = 1.0f;
    const Bvh2 bvh = Bvh2::build(m.triangles, c);
    EXPECT_EQ(bvh.validate(m.triangles), "") << m.name;
    const WideBvh wide = WideBvh::from_bvh2(bvh, m.triangles);
    EXPECT_EQ(wide.validate(m.triangles.size()), "") << m.name;
    if (m.triangles.size() > 100) {
      EXPECT_GT(bvh.prim_ids.size(), m.triangles.size()) << m.name << ": nothing was split";
    }
  }
}

TEST(BvhBuild, EqualCentroidsStillSplitDownToLeafSize) {
  // The builder bins box centres: 600 copies of one triangle make every centre equal, so
  // only the median fallback can split them; equal_centroids() shares vertex means only.
  for (const auto& tris : {std::vector<Triangle>(600, testing::random_soup(1, 3)[0]), testing::equal_centroids(600, 4)}) {
    const Bvh2 bvh = Bvh2::build(tris);
    EXPECT_EQ(bvh.validate(tris), "");
    for (const Bvh2Node& n : bvh.nodes) EXPECT_LE(n.count, 4);
    EXPECT_GE(bvh.nodes.size(), 2 * (600 / 4) - 1);
    EXPECT_LE(bvh.depth(), 24);
  }
  const Bvh2 same = Bvh2::build(std::vector<Triangle>(600, testing::random_soup(1, 3)[0]));
  EXPECT_LE(same.depth(), 8);  // median splits: ceil(log2(600 / 4))
}

// max_leaf_size is inclusive: copies of one triangle (no split can separate them) stay in one
// leaf up to that count, and one more is split by the median fallback.
TEST(BvhBuild, LeafHoldsExactlyUpToMaxLeafSizeTriangles) {
  const Triangle tri = testing::random_soup(1, 3)[0];
  for (int leaf : {1, 4, 15}) {
    BvhBuildConfig c;
    c.max_leaf_size = leaf;
    const Bvh2 full = Bvh2::build(std::vector<Triangle>(size_t(leaf), tri), c);
    ASSERT_EQ(full.nodes.size(), 1u) << leaf;
    EXPECT_EQ(full.nodes[0].count, leaf);
    const Bvh2 over = Bvh2::build(std::vector<Triangle>(size_t(leaf) + 1, tri), c);
    ASSERT_EQ(over.nodes.size(), 3u) << leaf;
    EXPECT_EQ(over.nodes[over.nodes[0].first].count + over.nodes[over.nodes[0].first + 1].count, leaf + 1);
  }
}

// A triangle in the plane y = 0 whose box is [x0, x0 + w] x {0} x [z0, z0 + d]: the builder's
// half area of such a box is its x z term alone, w d.
Triangle flat_in_y(float x0, float z0, float w, float d) {
  return {{x0, 0, z0}, {x0 + w, 0, z0}, {x0, 0, z0 + d}};
}

// The leaf-or-split decision in exact numbers (costs 1, leaf_block 1, half areas): two unit
// squares side by side give leaf 2 x 2 = 4 against split 2 + 1 + 1 = 4, a tie the leaf wins;
// one unit apart, leaf 2 x 3 = 6 loses to split 3 + 1 + 1 = 5.
TEST(BvhBuild, TwoTrianglesSplitOnlyWhenTheSplitCostsLessThanOneLeaf) {
  const Bvh2 tie = Bvh2::build(std::vector<Triangle>{flat_in_y(0, 0, 1, 1), flat_in_y(1, 0, 1, 1)});
  ASSERT_EQ(tie.nodes.size(), 1u);
  EXPECT_EQ(tie.nodes[0].count, 2);
  const Bvh2 apart = Bvh2::build(std::vector<Triangle>{flat_in_y(0, 0, 1, 1), flat_in_y(2, 0, 1, 1)});
  ASSERT_EQ(apart.nodes.size(), 3u);
  const Bvh2Node& left = apart.nodes[apart.nodes[0].first];
  const Bvh2Node& right = apart.nodes[apart.nodes[0].first + 1];
  EXPECT_EQ(left.count, 1);
  EXPECT_EQ(right.count, 1);
  EXPECT_EQ(left.bounds.hi.x, 1.0f);
  EXPECT_EQ(right.bounds.lo.x, 2.0f);
  EXPECT_EQ(apart.nodes[0].axis, 0);
}

// With leaf_block 4 a side of 4 triangles costs one block test, in the split's cost as in the
// leaf's: 4 copies of a unit square at x = 0 and 4 at x = 3 give leaf 2 blocks x 4 = 8 against
// split 4 + 1 + 1 = 6. Counted per triangle (4 + 4 x 1 + 4 x 1 = 12) the split would lose.
TEST(BvhBuild, SplitCostCountsLeafBlocksLikeTheLeafCost) {
  std::vector<Triangle> tris(4, flat_in_y(0, 0, 1, 1));
  tris.insert(tris.end(), 4, flat_in_y(3, 0, 1, 1));
  BvhBuildConfig c;
  c.leaf_block = 4;
  c.max_leaf_size = 8;
  const Bvh2 bvh = Bvh2::build(tris, c);
  ASSERT_EQ(bvh.nodes.size(), 3u);
  EXPECT_EQ(bvh.nodes[bvh.nodes[0].first].count, 4);
  EXPECT_EQ(bvh.nodes[bvh.nodes[0].first + 1].count, 4);
  EXPECT_EQ(bvh.validate(tris), "");
}

// Splits of equal cost: the first in sweep order (x, then y, then z) wins. Two unit squares
// on the diagonal of the x z plane are separated alike along x and along z.
TEST(BvhBuild, EqualCostSplitsGoToTheLowestAxis) {
  const Bvh2 bvh = Bvh2::build(std::vector<Triangle>{flat_in_y(0, 0, 1, 1), flat_in_y(2, 2, 1, 1)});
  ASSERT_EQ(bvh.nodes.size(), 3u);
  EXPECT_EQ(bvh.nodes[0].axis, 0);
}

TEST(BvhBuild, EmptyAndSingleTriangle) {
  const Bvh2 empty = Bvh2::build({});
  EXPECT_TRUE(empty.nodes.empty());
  EXPECT_EQ(empty.validate({}), "");
  EXPECT_EQ(WideBvh::build({}).validate(0), "");
  const std::vector<Triangle> one = {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}};
  const Bvh2 b = Bvh2::build(one);
  ASSERT_EQ(b.nodes.size(), 1u);
  EXPECT_TRUE(b.nodes[0].is_leaf());
  EXPECT_EQ(b.depth(), 0);
  const WideBvh w = WideBvh::build(one);
  EXPECT_EQ(w.validate(1), "");
  ASSERT_EQ(w.nodes.size(), 1u);
  EXPECT_EQ(w.nodes[0].count, 1u);
}

// Found by review: the scene loader refuses non-finite vertices, but the library's build took
// them (NaN made the tree depend on the thread count) and still must not.
TEST(BvhBuild, NonFiniteTrianglesAreInputErrors) {
  for (const float bad : {std::numeric_limits<float>::quiet_NaN(), kInfinity}) {
    const std::vector<Triangle> tris = {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 0, 1}, {1, bad, 1}, {0, 1, 1}}};
    try {
      Bvh2::build(tris);
      ADD_FAILURE() << "no error for " << bad;
    } catch (const InputError& e) {
      EXPECT_STREQ(e.what(), "BVH: triangle 1 has an infinite or NaN vertex");
    }
    EXPECT_THROW(WideBvh::build(tris), InputError);
  }
}

// Boxes without area cost every split 0: the first bin won at every level, peeling one bin
// off per node (depth 246 for these 50,000 collinear triangles). The median split halves them.
TEST(BvhBuild, BoxesWithoutAreaSplitAtTheMedian) {
  std::vector<Triangle> line;
  for (int i = 0; i < 50000; ++i) line.push_back({{float(i), 0, 0}, {i + 0.5f, 0, 0}, {i + 1.0f, 0, 0}});
  const Bvh2 bvh = Bvh2::build(line);
  EXPECT_EQ(bvh.validate(line), "");
  EXPECT_LE(bvh.depth(), 16);  // 50,000 / 8 per leaf needs 13 levels
}

TEST(BvhBuild, BadConfigIsAnInputError) {
  const auto tris = testing::random_soup(10, 1);
  BvhBuildConfig c;
  c.bins = 1;
  EXPECT_THROW(Bvh2::build(tris, c), InputError);
  c = {};
  c.max_leaf_size = 16;
  EXPECT_THROW(Bvh2::build(tris, c), InputError);
}

TEST(BvhBuild, RandomSoupTreeIsShallowAndItsLeavesHoldSeveralTriangles) {
  // A uniform soup: SAH keeps the tree near-balanced, at most twice the depth of a balanced
  // tree (log2 20000 = 14.3; measured 18), and a third of the triangles share leaves (measured
  // 13069 leaves).
  const auto tris = testing::random_soup(20000, 5);
  const Bvh2 bvh = Bvh2::build(tris);
  EXPECT_LE(bvh.depth(), 28);
  size_t leaves = 0;
  for (const Bvh2Node& n : bvh.nodes) leaves += n.is_leaf();
  EXPECT_EQ(bvh.nodes.size(), 2 * leaves - 1);
  EXPECT_LT(leaves, tris.size() * 3 / 4);
  const WideBvh wide = WideBvh::from_bvh2(bvh, tris);
  EXPECT_LT(wide.nodes.size() * 4, bvh.nodes.size());  // about 7 binary nodes per wide node
  EXPECT_LE(wide.depth(), bvh.depth() / 2 + 2);
}

TEST(BvhBuild, PresplitMeetsTheReferenceBudget) {
  // Triangles of random size: the budget is a fraction of the triangle count, met from below
  // (the floored per-triangle counts); the mean-priority scale used before gave far fewer.
  const auto tris = testing::random_soup(20000, 5);
  for (float budget : {0.05f, 0.3f, 1.0f}) {
    BvhBuildConfig c;
    c.presplit = budget;
    const Bvh2 bvh = Bvh2::build(tris, c);
    const double extra = double(bvh.prim_ids.size()) - double(tris.size());  // one slot per reference
    EXPECT_LE(extra, double(budget) * double(tris.size())) << budget;
    EXPECT_GE(extra, 0.95 * double(budget) * double(tris.size())) << budget;
  }
}

// Pre-splitting sums its reference counts in 64 bits and refuses a total the builder would
// refuse (2^27 or more) before allocating the references, with the builder's message. In 32
// bits, 65 references for each of 66 million triangles wrapped around; here two triangles of
// 2^31 references each wrap to 0 (max_extra is at most 64 in a build, but the sum is the same).
TEST(BvhBuild, PresplitRefusesMoreReferencesThanTheBuilderTakesBeforeAllocatingThem) {
  const double all = 1e30;  // a scale at which every triangle gets max_extra extra references
  const std::vector<float> one = {1.0f}, two = {1.0f, 1.0f};
  EXPECT_EQ(detail::reference_offsets(two, all, 2.0), (std::vector<uint32_t>{0, 3, 6}));
  EXPECT_EQ(detail::reference_offsets(two, 0.0, 64.0), (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(detail::reference_offsets(one, all, double((1u << 27) - 2)).back(), (1u << 27) - 1);
  auto refusal = [&](const std::vector<float>& priority, double max_extra) -> std::string {
    try {
      detail::reference_offsets(priority, all, max_extra);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(refusal(one, double((1u << 27) - 1)),
            "BVH: 134217728 primitives (triangles, or their pieces with presplit), at most 2^27 - 1 (134217727) supported");
  EXPECT_EQ(refusal(two, double((1u << 31) - 1)),
            "BVH: 4294967296 primitives (triangles, or their pieces with presplit), at most 2^27 - 1 (134217727) supported");
}

TEST(BvhBuild, OneAndTwoThreadsBuildIdenticalTrees) {
  const auto tris = testing::random_soup(testing::small_scale() ? 20000 : 100000, 9);
  BvhBuildConfig c;
  c.parallel_threshold = 1024;
  auto build_with = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    return Bvh2::build(tris, c);
  };
  for (float presplit : {0.0f, 0.3f}) {
    c.presplit = presplit;
    const Bvh2 a = build_with(1), b = build_with(2);
    ASSERT_EQ(a.nodes.size(), b.nodes.size());
    EXPECT_EQ(std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(Bvh2Node)), 0);
    EXPECT_EQ(a.prim_ids, b.prim_ids);
    EXPECT_EQ(a.depth(), b.depth());
  }
}

TEST(BvhValidate, DetectsCorruptedBinaryTrees) {
  const auto tris = testing::random_soup(500, 2);
  const Bvh2 good = Bvh2::build(tris);
  ASSERT_EQ(good.validate(tris), "");
  ASSERT_FALSE(good.nodes[0].is_leaf());
  const uint32_t left = good.nodes[0].first;

  Bvh2 b = good;  // a child sticking out of its parent
  b.nodes[left].bounds.hi.x += 1.0f;
  EXPECT_NE(b.validate(tris).find("not inside"), std::string::npos) << b.validate(tris);

  b = good;  // a triangle twice in its leaf, another lost
  const auto pair = std::find_if(good.nodes.begin(), good.nodes.end(), [](const Bvh2Node& n) { return n.count >= 2; });
  ASSERT_NE(pair, good.nodes.end());
  b.prim_ids[pair->first + 1] = b.prim_ids[pair->first];
  EXPECT_NE(b.validate(tris).find("twice"), std::string::npos) << b.validate(tris);

  b = good;  // a cycle back to the root's children
  for (auto& n : b.nodes)
    if (!n.is_leaf() && &n != &b.nodes[0]) { n.first = left; break; }
  EXPECT_NE(b.validate(tris), "");

  b = good;  // an empty-looking leaf turned inner with children out of range
  for (auto& n : b.nodes)
    if (n.is_leaf()) { n.count = 0; n.first = uint32_t(b.nodes.size()); break; }
  EXPECT_NE(b.validate(tris).find("out of range"), std::string::npos) << b.validate(tris);

  b = good;  // an unreachable extra node
  b.nodes.push_back(b.nodes.back());
  EXPECT_NE(b.validate(tris).find("unreachable"), std::string::npos) << b.validate(tris);

  b = good;  // two leaves swap a triangle, one of which lies outside the other's box (what
             // a builder whose partition disagrees with its bins would make)
  const auto leaf_of = [&](uint32_t k) {
    for (const Bvh2Node& n : good.nodes)
      if (n.is_leaf() && k >= n.first && k < n.first + n.count) return &n;
    return static_cast<const Bvh2Node*>(nullptr);
  };
  const uint32_t last = uint32_t(good.prim_ids.size() - 1);
  ASSERT_FALSE(leaf_of(0)->bounds.contains(tris[good.prim_ids[last]].bounds()));
  std::swap(b.prim_ids[0], b.prim_ids[last]);
  EXPECT_NE(b.validate(tris).find("outside the leaf box"), std::string::npos) << b.validate(tris);

  b = good;  // the leaf-ordered copy disagrees with the ids
  std::swap(b.leaf_tris[0], b.leaf_tris[1]);
  EXPECT_NE(b.validate(tris).find("] is not triangle"), std::string::npos) << b.validate(tris);
  b = good;
  b.leaf_tris.pop_back();
  EXPECT_NE(b.validate(tris).find("leaf_tris has"), std::string::npos) << b.validate(tris);

  std::vector<Triangle> more(tris.begin(), tris.end());
  more.push_back(tris[0]);
  EXPECT_NE(good.validate(more), "");  // a triangle missing
}

TEST(BvhValidate, DetectsCorruptedWideTrees) {
  const auto tris = testing::random_soup(2000, 3);
  const WideBvh good = WideBvh::build(tris);
  ASSERT_EQ(good.validate(tris.size()), "");
  ASSERT_GT(good.nodes.size(), 1u);

  WideBvh w = good;  // a child box too small for its subtree
  w.nodes[0].hi_x[0] = w.nodes[0].lo_x[0];
  EXPECT_NE(w.validate(tris.size()).find("inside"), std::string::npos) << w.validate(tris.size());

  w = good;  // a triangle twice (the last real slot's id copied to slot 0), another lost
  size_t last = w.prim_ids.size() - 1;
  while (w.prim_ids[last] == kInvalidId) --last;
  w.prim_ids[0] = w.prim_ids[last];
  EXPECT_NE(w.validate(tris.size()).find("twice"), std::string::npos) << w.validate(tris.size());

  w = good;  // a triangle moved out of its leaf's box
  w.leaf_blocks[0].v[0][0][0] += 10.0f;
  EXPECT_NE(w.validate(tris.size()).find("outside"), std::string::npos) << w.validate(tris.size());

  w = good;
  w.nodes[0].count = 0;
  EXPECT_NE(w.validate(tris.size()), "");

  w = good;
  w.nodes.emplace_back(w.nodes.back());
  EXPECT_NE(w.validate(tris.size()).find("unreachable"), std::string::npos) << w.validate(tris.size());
}

TEST(BvhBuild, RealSceneValidates) {
  const auto path = find_scene_file("sibenik/sibenik.obj");
  if (!path) GTEST_SKIP() << "sibenik/sibenik.obj not found under " << scenes_dir() << " (set RAYSCOUT_SCENES)";
  const Scene scene = load_scene(*path);
  const WideBvh wide = WideBvh::build(scene.triangles);
  EXPECT_EQ(wide.validate(scene.triangles.size()), "");
  const Bvh2 bvh = Bvh2::build(scene.triangles);
  EXPECT_EQ(bvh.validate(scene.triangles), "");
  EXPECT_LT(bvh.depth(), 64);
}

}  // namespace
}  // namespace rayscout
