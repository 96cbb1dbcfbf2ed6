// Bvh2 and WideBvh traversal: brute-force agreement per config, exact counters, start nodes.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "generated_scenes.h"
#include "rayscout/bvh/bvh_accelerators.h"
#include "rayscout/core/hit_compare.h"

namespace rayscout {
namespace {

std::vector<Triangle> quad_at(float x0) {  // two triangles spanning [x0, x0+1] x [0, 1] at z = 0
  return {{{x0, 0, 0}, {x0 + 1, 0, 0}, {x0 + 1, 1, 0}}, {{x0, 0, 0}, {x0 + 1, 1, 0}, {x0, 1, 0}}};
}

Ray down_at(float x, float y) { return {{x, y, 1.0f}, 0.0f, {0, 0, -1}, kInfinity}; }

TEST(BvhTraversal, MatchesBruteForceForLeafSizesAndBins) {
  for (const auto& m : testing::nasty_meshes()) {
    const RayBatch rays = testing::nasty_rays(m.triangles, 21);
    const auto [ref, ref_occ] = testing::brute_force(m.triangles, rays);
    for (int leaf : {1, 4, 15}) {
      BvhBuildConfig c;
      c.max_leaf_size = leaf;
      c.bins = leaf == 1 ? 8 : 32;
      c.presplit = leaf == 4 ? 1.0f : 0.0f;  // pieces of one triangle in several leaves
      const Bvh2 bvh = Bvh2::build(m.triangles, c);
      const WideBvh wide = WideBvh::from_bvh2(bvh, m.triangles);
      size_t bad = 0, bad_occ = 0;
      for (size_t i = 0; i < rays.size(); ++i) {
        const Hit a = bvh.intersect<false>(rays[i], {}, nullptr);
        const Hit b = wide.intersect<false>(rays[i], {}, nullptr);
        const Hit r = ref[i];
        bad += a.prim != r.prim || a.t != r.t || a.u != r.u || a.v != r.v;
        bad += b.prim != r.prim || b.t != r.t || b.u != r.u || b.v != r.v;
        bad_occ += bvh.occluded<false>(rays[i], {}, nullptr) != bool(ref_occ[i]);
        bad_occ += wide.occluded<false>(rays[i], {}, nullptr) != bool(ref_occ[i]);
      }
      EXPECT_EQ(bad, 0u) << m.name << " leaf " << leaf;
      EXPECT_EQ(bad_occ, 0u) << m.name << " leaf " << leaf;
    }
  }
}

TEST(BvhTraversal, CountersAreExactOnAHandCheckedScene) {
  // Two quads far apart: the root splits them, each quad is one leaf of two triangles.
  std::vector<Triangle> tris = quad_at(0.0f);
  for (const auto& t : quad_at(10.0f)) tris.push_back(t);
  const Bvh2 bvh = Bvh2::build(tris);
  ASSERT_EQ(bvh.nodes.size(), 3u);
  TraceStats s;
  const Hit h = bvh.intersect<true>(down_at(0.75f, 0.25f), {}, &s);
  EXPECT_EQ(h.prim, 0u);
  EXPECT_EQ(h.t, 1.0f);
  EXPECT_EQ(s.traversal_steps, 2u);  // root, left leaf
  EXPECT_EQ(s.ray_box_tests, 3u);    // root box, both children
  EXPECT_EQ(s.ray_tri_tests, 2u);    // both triangles of the leaf
  EXPECT_EQ(s.rays, 0u);

  s = {};
  EXPECT_FALSE(bvh.occluded<true>(down_at(5.0f, 0.5f), {}, &s));  // between the quads
  EXPECT_EQ(s.traversal_steps, 1u);
  EXPECT_EQ(s.ray_box_tests, 3u);
  EXPECT_EQ(s.ray_tri_tests, 0u);

  const WideBvh wide = WideBvh::from_bvh2(bvh, tris);
  ASSERT_EQ(wide.nodes.size(), 1u);
  s = {};
  EXPECT_EQ(wide.intersect<true>(down_at(10.25f, 0.75f), {}, &s).prim, 3u);
  EXPECT_EQ(s.traversal_steps, 2u);  // root node, one leaf
  EXPECT_EQ(s.ray_box_tests, 2u);    // the root's two used slots
  EXPECT_EQ(s.ray_tri_tests, 2u);
  s = {};
  EXPECT_TRUE(wide.occluded<true>(down_at(0.75f, 0.25f), {}, &s));
  EXPECT_EQ(s.traversal_steps, 2u);
  EXPECT_EQ(s.ray_box_tests, 2u);
  EXPECT_EQ(s.ray_tri_tests, 2u);  // one block test of the leaf's two triangles
}

// Unit quads stacked at z = 0, 1, ..., n - 1 (quad k: triangles 2k, 2k + 1).
std::vector<Triangle> stacked_quads(int n) {
  std::vector<Triangle> tris;
  for (int k = 0; k < n; ++k)
    for (Triangle t : quad_at(0.0f)) {
      t.v0.z = t.v1.z = t.v2.z = float(k);
      tris.push_back(t);
    }
  return tris;
}

// A vertical ray at (0.75, 0.25) reaching the top (down) or bottom (up) quad of n at t = 1.
Ray through_stack(int n, bool down) {
  return down ? Ray{{0.75f, 0.25f, float(n)}, 0.0f, {0, 0, -1}, kInfinity}
              : Ray{{0.75f, 0.25f, -1.0f}, 0.0f, {0, 0, 1}, kInfinity};
}

// Closest hit visits the nearer child first and culls farther boxes once a hit is nearer:
// a ray through stacked quads tests only the first quad it meets, from above and from below.
// Visiting a farther child first, or not shortening the cull distance at a hit, finds the
// same hit after testing every quad.
TEST(BvhTraversal, NearerChildFirstAndFartherBoxesCulledAfterAHit) {
  const auto two = stacked_quads(2), four = stacked_quads(4);
  const Bvh2 bvh2 = Bvh2::build(two), bvh4 = Bvh2::build(four);
  ASSERT_EQ(bvh2.nodes.size(), 3u);
  ASSERT_EQ(bvh4.nodes.size(), 7u);
  const WideBvh wide2 = WideBvh::from_bvh2(bvh2, two), wide4 = WideBvh::from_bvh2(bvh4, four);
  ASSERT_EQ(wide2.nodes.size(), 1u);
  ASSERT_EQ(wide2.nodes[0].count, 2u);  // the wide traversal's two-child path
  ASSERT_EQ(wide4.nodes.size(), 1u);
  ASSERT_EQ(wide4.nodes[0].count, 4u);  // its path for three or more children
  for (const bool down : {true, false}) {
    const char* dir = down ? "down" : "up";
    TraceStats s;
    Hit h = bvh2.intersect<true>(through_stack(2, down), {}, &s);
    EXPECT_EQ(h.prim, down ? 2u : 0u) << dir;
    EXPECT_EQ(h.t, 1.0f) << dir;
    EXPECT_EQ(s.traversal_steps, 2u) << dir;  // root, the near leaf
    EXPECT_EQ(s.ray_tri_tests, 2u) << dir;
    s = {};
    h = bvh4.intersect<true>(through_stack(4, down), {}, &s);
    EXPECT_EQ(h.prim, down ? 6u : 0u) << dir;
    EXPECT_EQ(h.t, 1.0f) << dir;
    EXPECT_EQ(s.traversal_steps, 3u) << dir;  // root, the near inner node, the near leaf
    EXPECT_EQ(s.ray_tri_tests, 2u) << dir;
    s = {};
    h = wide2.intersect<true>(through_stack(2, down), {}, &s);
    EXPECT_EQ(h.prim, down ? 2u : 0u) << dir;
    EXPECT_EQ(s.traversal_steps, 2u) << dir;
    EXPECT_EQ(s.ray_tri_tests, 2u) << dir;
    s = {};
    h = wide4.intersect<true>(through_stack(4, down), {}, &s);
    EXPECT_EQ(h.prim, down ? 6u : 0u) << dir;
    EXPECT_EQ(s.traversal_steps, 2u) << dir;
    EXPECT_EQ(s.ray_tri_tests, 2u) << dir;
  }
}

TEST(BvhTraversal, StatsPathGivesTheSameResultsAndSummedCounts) {
  const auto tris = testing::random_soup(3000, 8);
  const RayBatch rays = testing::random_rays(4000, 9);
  const Scene scene = testing::scene_from_triangles(tris);
  for (int wide : {0, 1}) {
    std::unique_ptr<Accelerator> accel;
    if (wide) accel = std::make_unique<WideBvhAccelerator>(scene.triangles);
    else accel = std::make_unique<Bvh2Accelerator>(scene.triangles);
    HitBatch plain, counted;
    TraceStats batch;
    accel->intersect(rays, plain);
    accel->intersect(rays, counted, &batch);
    EXPECT_TRUE(compare_hits(plain, counted, 0.0f).ok());
    EXPECT_EQ(plain.prim, counted.prim);
    // The batch counters equal the sum of the single-ray counters.
    TraceStats sum;
    const auto* w = dynamic_cast<WideBvhAccelerator*>(accel.get());
    const auto* b = dynamic_cast<Bvh2Accelerator*>(accel.get());
    for (size_t i = 0; i < rays.size(); ++i) {
      if (w) w->bvh().intersect<true>(rays[i], {}, &sum);
      else b->bvh().intersect<true>(rays[i], {}, &sum);
    }
    EXPECT_EQ(batch.rays, rays.size());
    EXPECT_EQ(batch.traversal_steps, sum.traversal_steps) << accel->name();
    EXPECT_EQ(batch.ray_box_tests, sum.ray_box_tests) << accel->name();
    EXPECT_EQ(batch.ray_tri_tests, sum.ray_tri_tests) << accel->name();
    EXPECT_GT(sum.ray_tri_tests, 0u);
    EXPECT_LT(sum.ray_tri_tests, rays.size() * tris.size() / 20) << "the tree should cull most triangles";

    std::vector<uint8_t> occ_plain, occ_counted;
    TraceStats occ_stats;
    accel->occluded(rays, occ_plain);
    accel->occluded(rays, occ_counted, &occ_stats);
    EXPECT_EQ(occ_plain, occ_counted);
    EXPECT_EQ(occ_stats.rays, rays.size());
    EXPECT_LE(occ_stats.ray_tri_tests, batch.ray_tri_tests) << "any hit stops early";
    EXPECT_LT(occ_stats.traversal_steps, batch.traversal_steps) << "any hit stops early";
    EXPECT_GT(accel->build_info().memory_bytes, 0u);
  }
}

TEST(BvhTraversal, StartingFromTheRootsChildrenEqualsStartingFromTheRoot) {
  const auto tris = testing::random_soup(3000, 4);
  const RayBatch rays = testing::random_rays(3000, 5);
  const Bvh2 bvh = Bvh2::build(tris);
  const WideBvh wide = WideBvh::from_bvh2(bvh, tris);
  const uint32_t kids[2] = {bvh.nodes[0].first, bvh.nodes[0].first + 1};
  const std::vector<uint32_t> wide_kids(wide.nodes[0].child, wide.nodes[0].child + wide.nodes[0].count);
  size_t hits = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const Hit a = bvh.intersect<false>(rays[i], {}, nullptr);
    const Hit b = bvh.intersect<false>(rays[i], kids, nullptr);
    const Hit c = wide.intersect<false>(rays[i], wide_kids, nullptr);
    EXPECT_EQ(a.prim, b.prim);
    EXPECT_EQ(a.t, b.t);
    EXPECT_EQ(a.prim, c.prim);
    EXPECT_EQ(a.t, c.t);
    EXPECT_EQ(bvh.occluded<false>(rays[i], {}, nullptr), bvh.occluded<false>(rays[i], kids, nullptr));
    EXPECT_EQ(wide.occluded<false>(rays[i], {}, nullptr), wide.occluded<false>(rays[i], wide_kids, nullptr));
    hits += a.hit();
  }
  EXPECT_GT(hits, rays.size() / 4);
}

TEST(BvhTraversal, StartingFromNodesThatMissTheGeometryGivesAMiss) {
  std::vector<Triangle> tris;
  for (int i = 0; i < 8; ++i)
    for (const auto& t : quad_at(float(i) * 1.5f)) tris.push_back(t);  // quads at x = 0 .. 11.5
  for (const auto& t : quad_at(100.0f)) tris.push_back(t);            // one far quad
  const Bvh2 bvh = Bvh2::build(tris);
  const WideBvh wide = WideBvh::from_bvh2(bvh, tris);
  // Nodes and wide refs whose boxes lie left of x = 50: they miss a ray at x = 100.5.
  std::vector<uint32_t> near_nodes, near_refs;
  for (uint32_t i = 0; i < bvh.nodes.size(); ++i)
    if (bvh.nodes[i].bounds.hi.x < 50.0f) near_nodes.push_back(i);
  for (uint32_t c = 0; c < wide.nodes[0].count; ++c)
    if (wide.nodes[0].child_bounds(int(c)).hi.x < 50.0f) near_refs.push_back(wide.nodes[0].child[c]);
  ASSERT_FALSE(near_nodes.empty());
  ASSERT_FALSE(near_refs.empty());
  const Ray far_ray = down_at(100.5f, 0.25f), near_ray = down_at(3.25f, 0.75f);
  EXPECT_TRUE(bvh.intersect<false>(far_ray, {}, nullptr).hit());
  EXPECT_TRUE(wide.intersect<false>(far_ray, {}, nullptr).hit());
  EXPECT_FALSE(bvh.intersect<false>(far_ray, near_nodes, nullptr).hit());
  EXPECT_FALSE(bvh.occluded<false>(far_ray, near_nodes, nullptr));
  EXPECT_FALSE(wide.intersect<false>(far_ray, near_refs, nullptr).hit());
  EXPECT_FALSE(wide.occluded<false>(far_ray, near_refs, nullptr));
  // ...and still find what they do contain.
  EXPECT_EQ(bvh.intersect<false>(near_ray, near_nodes, nullptr).prim,
            bvh.intersect<false>(near_ray, {}, nullptr).prim);
  EXPECT_EQ(wide.intersect<false>(near_ray, near_refs, nullptr).prim, bvh.intersect<false>(near_ray, {}, nullptr).prim);
  EXPECT_TRUE(wide.intersect<false>(near_ray, near_refs, nullptr).hit());
}

// k copies of a slanted triangle, 0.01 apart in x, that a ray down from (0.5, 0.375, 10)
// crosses at z = 8.5 (t = 1.5) while their boxes reach z = 0 (t = 10): with tmin = 5 every box
// test passes and only the triangle tests' tmin leaves them out.
std::vector<Triangle> slanted_blockers(int k) {
  std::vector<Triangle> tris;
  for (int i = 0; i < k; ++i) {
    const float dx = 0.01f * float(i);
    tris.push_back({{-2 + dx, 0.25f, 9}, {3 + dx, 0.25f, 9}, {0.5f + dx, 2.5f, 0}});
  }
  return tris;
}

// The segment [tmin, tmax] is where a hit counts: a triangle before tmin neither occludes nor
// is the closest hit (the accelerator suite in tests/accelerators checks it against brute only
// in bulk). One blocker and six; built by default, and as one leaf (for the wide BVH, over two
// 4-triangle blocks); the ray straight down (infinite inverse direction: the general child
// test) and tilted (the finite one); the trees' single rays and the accelerators' batches.
TEST(BvhTraversal, ABlockerBeforeTminNeitherOccludesNorIsHit) {
  const Ray straight{{0.5f, 0.375f, 10.0f}, 5.0f, {0, 0, -1}, kInfinity};
  const Ray tilted{{0.5f, 0.375f, 10.0f}, 5.0f, {0.03125f, 0.0625f, -1}, 20.0f};  // blockers at t = 2
  BvhBuildConfig one_leaf = wide_bvh_default_config();
  one_leaf.max_leaf_size = one_leaf.collapse_max_leaf = 8;
  one_leaf.traversal_cost = 100.0f;  // any split costs more than the leaf
  for (const int k : {1, 6}) {
    std::vector<Triangle> tris = slanted_blockers(k);
    const uint32_t target = uint32_t(tris.size());  // a quad [-1, 2]^2 beyond tmin, at z = 0 (t = 10)
    for (Triangle t : quad_at(-1.0f)) {
      for (Vec3* v : {&t.v0, &t.v1, &t.v2}) v->y = 3.0f * v->y - 1.0f, v->x = 3.0f * v->x + 2.0f;
      tris.push_back(t);
    }
    for (const bool with_target : {false, true}) {
      const std::vector<Triangle> scene_tris(tris.begin(), with_target ? tris.end() : tris.begin() + k);
      const Scene scene = testing::scene_from_triangles(scene_tris);
      const Bvh2Accelerator bvh_accel(scene.triangles);
      const WideBvhAccelerator wide_accel(scene.triangles);
      for (const bool leaf : {false, true}) {
        const BvhBuildConfig c = leaf ? one_leaf : BvhBuildConfig{};
        const Bvh2 bvh = Bvh2::build(scene_tris, c);
        const WideBvh wide = WideBvh::from_bvh2(bvh, scene_tris, c);
        if (leaf) {
          ASSERT_EQ(bvh.nodes.size(), 1u);
        }
        for (const Ray& ray : {straight, tilted}) {
          const std::string at = "k " + std::to_string(k) + (with_target ? " target" : "") + (leaf ? " one leaf" : "") +
                                 (ray.dir.x == 0.0f ? " straight" : " tilted");
          // The quad's triangle below the diagonal y = x for the straight ray, above it for the tilted one.
          const uint32_t expected = !with_target ? kInvalidId : ray.dir.x == 0.0f ? target : target + 1;
          Ray from_zero = ray;
          from_zero.tmin = 0.0f;  // the blockers are hit at t < 5
          ASSERT_TRUE(bvh.occluded<false>(from_zero, {}, nullptr)) << at;
          const Hit blocker = bvh.intersect<false>(from_zero, {}, nullptr);
          ASSERT_LT(blocker.prim, uint32_t(k)) << at;
          ASSERT_LT(blocker.t, ray.tmin) << at;

          TraceStats s;
          for (const Hit& h : {bvh.intersect<false>(ray, {}, nullptr), bvh.intersect<true>(ray, {}, &s),
                               wide.intersect<false>(ray, {}, nullptr), wide.intersect<true>(ray, {}, &s)}) {
            EXPECT_EQ(h.prim, expected) << at;
            if (with_target) {
              EXPECT_GT(h.t, ray.tmin) << at;
            }
          }
          EXPECT_EQ(bvh.occluded<false>(ray, {}, nullptr), with_target) << at;
          EXPECT_EQ(bvh.occluded<true>(ray, {}, &s), with_target) << at;
          EXPECT_EQ(wide.occluded<false>(ray, {}, nullptr), with_target) << at;
          EXPECT_EQ(wide.occluded<true>(ray, {}, &s), with_target) << at;
          if (leaf) continue;
          RayBatch batch;
          batch.push_back(ray);
          HitBatch hits;
          std::vector<uint8_t> occ;
          for (const Accelerator* accel : {static_cast<const Accelerator*>(&bvh_accel), static_cast<const Accelerator*>(&wide_accel)}) {
            accel->intersect(batch, hits);
            accel->occluded(batch, occ);
            EXPECT_EQ(hits.prim[0], expected) << at << " " << accel->name();
            EXPECT_EQ(occ[0], with_target ? 1 : 0) << at << " " << accel->name();
          }
        }
      }
    }
  }
}

// A box that ends before tmin is culled by the box test: the leaf of a blocker quad at t = 2
// costs no visit to a ray with tmin = 5 that reaches the other quad at t = 10, from above and
// from below (without that cull the triangle tests would still give the right answer, after a
// visit and two more tests, or none when the other leaf is visited first and is hit).
TEST(BvhTraversal, ABoxBeforeTminIsNotEntered) {
  std::vector<Triangle> tris = stacked_quads(2);
  for (Triangle& t : tris)
    if (t.v0.z > 0.0f) t.v0.z = t.v1.z = t.v2.z = 8.0f;  // quads at z = 0 and z = 8
  const Bvh2 bvh = Bvh2::build(tris);
  ASSERT_EQ(bvh.nodes.size(), 3u);
  const WideBvh wide = WideBvh::from_bvh2(bvh, tris);
  ASSERT_EQ(wide.nodes.size(), 1u);
  for (const bool down : {true, false}) {
    const char* dir = down ? "down" : "up";
    const Ray ray = down ? Ray{{0.75f, 0.25f, 10.0f}, 5.0f, {0, 0, -1}, kInfinity}
                         : Ray{{0.75f, 0.25f, -2.0f}, 5.0f, {0, 0, 1}, kInfinity};
    TraceStats s;
    EXPECT_EQ(bvh.intersect<true>(ray, {}, &s).prim, down ? 0u : 2u) << dir;
    EXPECT_EQ(s.traversal_steps, 2u) << dir;  // root, the far leaf
    EXPECT_EQ(s.ray_tri_tests, 2u) << dir;
    s = {};
    EXPECT_TRUE(bvh.occluded<true>(ray, {}, &s)) << dir;
    EXPECT_EQ(s.traversal_steps, 2u) << dir;
    s = {};
    EXPECT_EQ(wide.intersect<true>(ray, {}, &s).prim, down ? 0u : 2u) << dir;
    EXPECT_EQ(s.traversal_steps, 2u) << dir;
    EXPECT_EQ(s.ray_tri_tests, 2u) << dir;
    s = {};
    EXPECT_TRUE(wide.occluded<true>(ray, {}, &s)) << dir;
    EXPECT_EQ(s.traversal_steps, 2u) << dir;
    EXPECT_EQ(s.ray_tri_tests, 2u) << dir;
  }
}

TEST(BvhTraversal, EmptyTreeMisses) {
  const Bvh2 bvh = Bvh2::build({});
  const WideBvh wide = WideBvh::build({});
  EXPECT_FALSE(bvh.intersect<false>(down_at(0, 0), {}, nullptr).hit());
  EXPECT_EQ(bvh.intersect<false>(down_at(0, 0), {}, nullptr).t, kInfinity);
  EXPECT_FALSE(wide.intersect<false>(down_at(0, 0), {}, nullptr).hit());
  EXPECT_FALSE(wide.occluded<false>(down_at(0, 0), {}, nullptr));
}

}  // namespace
}  // namespace rayscout
