// compare_hits / compare_occlusion: ties, grazing contacts, t percentiles, tolerance.
#include <gtest/gtest.h>

#include <cmath>

#include "rayscout/core/hit_compare.h"

namespace rayscout {
namespace {

HitBatch batch(std::initializer_list<Hit> hits) {
  HitBatch b;
  b.reset(hits.size());
  size_t i = 0;
  for (const Hit& h : hits) b.set(i++, h);
  return b;
}

TEST(HitCompare, IdenticalBatchesAgreeBitExactly) {
  const HitBatch a = batch({{1.0f, 3, 0.2f, 0.3f}, {}, {2.0f, 1, 0.1f, 0.1f}});
  const HitDiff d = compare_hits(a, a, 0.0f);
  EXPECT_TRUE(d.ok());
  EXPECT_EQ(d.rays, 3u);
  EXPECT_EQ(d.both_hit, 2u);
  EXPECT_EQ(d.max_rel_diff, 0.0);
}

// Found by fuzzing: a hit at t = +-inf (a denormal direction, see ray_file_test) compared
// with itself gave a NaN difference (inf - inf), counted as a distance mismatch: two identical
// HITS files were DIFFERENT.
TEST(HitCompare, IdenticalHitsAtAnInfiniteDistanceAgree) {
  const HitBatch a = batch({{kInfinity, 3, 0.2f, 0.3f}, {-kInfinity, 1, 0.1f, 0.1f}, {2.0f, 1, 0.1f, 0.1f}});
  for (float tol : {0.0f, 1e-4f}) {
    const HitDiff d = compare_hits(a, a, tol);
    EXPECT_TRUE(d.ok()) << d.first;
    EXPECT_EQ(d.t_mismatch, 0u);
    EXPECT_EQ(d.max_rel_diff, 0.0);
  }
  const HitBatch b = batch({{kInfinity, 3, 0.2f, 0.3f}, {kInfinity, 1, 0.1f, 0.1f}, {2.0f, 1, 0.1f, 0.1f}});
  EXPECT_EQ(compare_hits(a, b, 1e-4f).t_mismatch, 1u);  // -inf against +inf still differs
}

TEST(HitCompare, DistanceToleranceIsRelativeAboveOne) {
  const HitBatch ref = batch({{100.0f, 3, 0.2f, 0.3f}, {0.5f, 4, 0.2f, 0.3f}});
  const HitBatch got = batch({{100.005f, 3, 0.2f, 0.3f}, {0.50002f, 4, 0.2f, 0.3f}});
  HitDiff d = compare_hits(ref, got, 1e-4f);
  EXPECT_TRUE(d.ok());
  EXPECT_NEAR(d.max_rel_diff, 5e-5, 1e-6);
  EXPECT_NEAR(d.p99_rel_diff, 5e-5, 1e-6);
  d = compare_hits(ref, got, 1e-5f);
  EXPECT_EQ(d.t_mismatch, 2u);
  EXPECT_FALSE(d.ok());
}

// With the rays, the tolerance is world space: a short direction 50 units from the origin
// (the case of Sponza's floor seen along a 1e-3-long direction, t 79.26 vs 79.25) agrees,
// while the same t error on a unit direction near the origin does not.
TEST(HitCompare, WorldSpaceToleranceWithRays) {
  RayBatch rays;
  rays.push_back({{-49.5f, -11.4f, -7.3f}, 0.0f, {8.9e-4f, -6.1e-4f, 6.2e-5f}, kInfinity});
  rays.push_back({{0.1f, 0.2f, 0.0f}, 0.0f, {0.0f, 0.0f, 1.0f}, kInfinity});
  const HitBatch ref = batch({{79.2638f, 3, 0.2f, 0.3f}, {0.5f, 4, 0.2f, 0.3f}});
  const HitBatch got = batch({{79.2450f, 3, 0.2f, 0.3f}, {0.5002f, 4, 0.2f, 0.3f}});
  HitCompareConfig cfg;
  cfg.rel_tol = 1e-4f;
  HitDiff d = compare_hits(ref, got, cfg);
  EXPECT_EQ(d.t_mismatch, 2u);  // relative to t: 2.4e-4 and 2e-4
  cfg.rays = &rays;
  d = compare_hits(ref, got, cfg);
  EXPECT_EQ(d.t_mismatch, 1u);  // world: 2.0e-5 units at |o| = 49.5 agrees; 2e-4 at |o| < 1 does not
  EXPECT_NE(d.first.find("ray 1:"), std::string::npos) << d.first;
  EXPECT_NEAR(d.max_rel_diff, 2e-4, 1e-5);
  // A hit 1e-3 world units from an origin at 49.5 is a contact at t ~ 0 in world space.
  const Hit touch{1.0f, 3, 0.3f, 0.3f};
  cfg.rel_tol = 1e-4f;
  EXPECT_TRUE(is_grazing({0.05f, 3, 0.3f, 0.3f}, cfg, 0));   // 5.4e-5 units
  EXPECT_FALSE(is_grazing(touch, cfg, 1));                  // 1 unit from the origin
}

// Without rays the scale is max(1, |t_ref|): below t = 1 the tolerance is absolute. Powers
// of two throughout, so every ratio is exact: a 2^-13 difference at t = 0.25 agrees with a
// tolerance of 2^-12, where a tolerance relative to t (2^-11) would not.
TEST(HitCompare, ToleranceWithoutRaysIsAbsoluteBelowOne) {
  const HitBatch ref = batch({{0.25f, 3, 0.2f, 0.3f}});
  const HitBatch got = batch({{0.25f + 0x1p-13f, 3, 0.2f, 0.3f}});
  const HitDiff d = compare_hits(ref, got, 0x1p-12f);
  EXPECT_TRUE(d.ok()) << d.first;
  EXPECT_EQ(d.max_rel_diff, 0x1p-13);
}

// With rays the world scale is max(1, |o|, |o + t d|) / |d| (max norms), each of the three
// deciding one ray: a hit 128 units out from the origin, a ray from 128 units in to the
// origin, and a short ray near the origin on a direction of length 2. Each differs by 2^-13
// of its scale and agrees with a tolerance of 2^-12; a scale without the hit point (first
// ray) or without the origin (second) would be 2^7 times too small.
TEST(HitCompare, WorldScaleIsTheLargestOfOneTheOriginAndTheHitPoint) {
  RayBatch rays;
  rays.push_back({{0.0f, 0.0f, 0.0f}, 0.0f, {1.0f, 0.0f, 0.0f}, kInfinity});     // hit at x = 128
  rays.push_back({{128.0f, 0.0f, 0.0f}, 0.0f, {-1.0f, 0.0f, 0.0f}, kInfinity});  // hit at the origin
  rays.push_back({{0.5f, 0.0f, 0.0f}, 0.0f, {0.0f, 0.0f, 2.0f}, kInfinity});     // hit at (0.5, 0, 0.5)
  const HitBatch ref = batch({{128.0f, 3, 0.2f, 0.3f}, {128.0f, 4, 0.2f, 0.3f}, {0.25f, 5, 0.2f, 0.3f}});
  const HitBatch got = batch({{128.0f + 0x1p-6f, 3, 0.2f, 0.3f}, {128.0f + 0x1p-6f, 4, 0.2f, 0.3f},
                              {0.25f + 0x1p-14f, 5, 0.2f, 0.3f}});
  HitCompareConfig cfg;
  cfg.rel_tol = 0x1p-12f;
  cfg.rays = &rays;
  HitDiff d = compare_hits(ref, got, cfg);
  EXPECT_TRUE(d.ok()) << d.first;
  EXPECT_EQ(d.both_hit, 3u);
  EXPECT_EQ(d.max_rel_diff, 0x1p-13);
  EXPECT_EQ(d.p99_rel_diff, 0x1p-13);
  cfg.rel_tol = 0x1p-14f;  // and each is a mismatch at a quarter of that tolerance
  d = compare_hits(ref, got, cfg);
  EXPECT_EQ(d.t_mismatch, 3u);
}

// A contact is grazing when u, v or w = 1 - u - v is <= edge_eps, bound included. edge_eps
// 1/8 and barycentrics in eighths keep w exact.
TEST(HitCompare, GrazingBoundIsInclusiveOnEachBarycentric) {
  HitCompareConfig cfg;
  cfg.edge_eps = 0.125f;
  EXPECT_TRUE(is_grazing({2.0f, 1, 0.125f, 0.5f}, cfg));   // u = edge_eps
  EXPECT_TRUE(is_grazing({2.0f, 1, 0.5f, 0.125f}, cfg));   // v = edge_eps
  EXPECT_TRUE(is_grazing({2.0f, 1, 0.5f, 0.375f}, cfg));   // w = edge_eps
  EXPECT_TRUE(is_grazing({2.0f, 1, 0.25f, 0.75f}, cfg));   // w = 0: on the edge v0 is opposite
  EXPECT_FALSE(is_grazing({2.0f, 1, 0.25f, 0.5f}, cfg));   // u, v, w = 1/4, 1/2, 1/4: inside
  EXPECT_FALSE(is_grazing({2.0f, 1, 0.5f, 0.25f}, cfg));   // 1/2, 1/4, 1/4
  EXPECT_FALSE(is_grazing({}, cfg));                       // a miss is no contact
  // In compare_hits: the reference's w-edge hit the candidate passed by is excused.
  cfg.rel_tol = 1e-4f;
  cfg.allow_grazing = true;
  const HitDiff d = compare_hits(batch({{2.0f, 1, 0.5f, 0.375f}}), batch({{}}), cfg);
  EXPECT_EQ(d.grazing, 1u);
  EXPECT_TRUE(d.ok()) << d.first;
}

TEST(HitCompare, TiesAreCountedNotErrors) {
  const HitBatch ref = batch({{1.0f, 3, 0.2f, 0.3f}, {1.0f, 3, 0.2f, 0.3f}});
  const HitBatch got = batch({{1.0f, 9, 0.2f, 0.3f}, {1.5f, 9, 0.2f, 0.3f}});
  const HitDiff d = compare_hits(ref, got, 1e-4f);
  EXPECT_EQ(d.ties, 1u);
  EXPECT_EQ(d.other_prim, 1u);
  EXPECT_NE(d.first.find("ray 1: different triangle"), std::string::npos) << d.first;
}

// Tolerance 0 is the accelerators' bit-identity check: a tie broken the other way and
// barycentrics that differ in the last bit are errors there.
TEST(HitCompare, ToleranceZeroAllowsNoTiesAndComparesBarycentrics) {
  const HitBatch ref = batch({{1.0f, 3, 0.2f, 0.3f}, {1.0f, 3, 0.2f, 0.3f}, {1.0f, 3, 0.2f, 0.3f}});
  const HitBatch got = batch({{1.0f, 9, 0.2f, 0.3f}, {1.0f, 3, std::nextafter(0.2f, 1.0f), 0.3f}, {1.0f, 3, 0.2f, 0.3f}});
  HitDiff d = compare_hits(ref, got, 0.0f);
  EXPECT_EQ(d.other_prim, 1u);
  EXPECT_EQ(d.ties, 0u);
  EXPECT_EQ(d.uv_mismatch, 1u);
  EXPECT_FALSE(d.ok());
  EXPECT_NE(d.first.find("ray 0: different triangle"), std::string::npos) << d.first;
  d = compare_hits(ref, got, 1e-6f);  // any tolerance: a tie, and u, v are not compared
  EXPECT_EQ(d.ties, 1u);
  EXPECT_EQ(d.uv_mismatch, 0u);
  EXPECT_TRUE(d.ok());
}

// Bit-identical means the bits of t too: -0 == +0, yet a hit at t = -0 (a ray starting on
// the triangle's plane) is not the same result as one at +0.
TEST(HitCompare, ToleranceZeroTellsTheSignOfAZeroDistance) {
  const HitBatch ref = batch({{0.0f, 3, 0.2f, 0.3f}});
  const HitBatch got = batch({{-0.0f, 3, 0.2f, 0.3f}});
  HitDiff d = compare_hits(ref, got, 0.0f);
  EXPECT_EQ(d.t_mismatch, 1u);
  EXPECT_FALSE(d.ok());
  EXPECT_TRUE(compare_hits(ref, got, 1e-6f).ok());
}

TEST(HitCompare, GrazingContactsOnlyWhenAllowed) {
  // ray 0: the reference touches an edge (v = 0) the candidate passed by;
  // ray 1: the candidate hits at the origin (t = 0) of a ray leaving a surface;
  // ray 2: an interior hit missed: always an error.
  const HitBatch ref = batch({{1.0f, 3, 0.5f, 0.0f}, {}, {1.0f, 5, 0.3f, 0.3f}});
  const HitBatch got = batch({{2.0f, 4, 0.3f, 0.3f}, {0.0f, 2, 0.3f, 0.3f}, {}});
  HitCompareConfig cfg;
  cfg.rel_tol = 1e-4f;
  HitDiff d = compare_hits(ref, got, cfg);
  EXPECT_EQ(d.other_prim, 1u);
  EXPECT_EQ(d.hit_miss, 2u);
  cfg.allow_grazing = true;
  d = compare_hits(ref, got, cfg);
  EXPECT_EQ(d.grazing, 2u);
  EXPECT_EQ(d.other_prim, 0u);
  EXPECT_EQ(d.hit_miss, 1u);
  EXPECT_NE(d.first.find("ray 2: hit/miss"), std::string::npos) << d.first;
  // Tolerance 0 is bit-identical: a grazing contact is an error like any other.
  cfg.rel_tol = 0.0f;
  d = compare_hits(ref, got, cfg);
  EXPECT_EQ(d.grazing, 0u);
  EXPECT_EQ(d.other_prim, 1u);
  EXPECT_EQ(d.hit_miss, 2u);
}

TEST(HitCompare, NinetyNinthPercentile) {
  HitBatch ref, got;
  ref.reset(1000);
  got.reset(1000);
  for (size_t i = 0; i < 1000; ++i) {
    ref.set(i, {10.0f, uint32_t(i), 0.3f, 0.3f});
    got.set(i, {10.0f + (i >= 990 ? 0.01f : 0.0f), uint32_t(i), 0.3f, 0.3f});  // 1 % differ by 1e-3
  }
  const HitDiff d = compare_hits(ref, got, 1e-2f);
  EXPECT_NEAR(d.max_rel_diff, 1e-3, 1e-5);
  EXPECT_EQ(d.p99_rel_diff, 0.0);  // the 990th smallest of 1000 is still 0
}

TEST(HitCompare, SizeMismatchIsAnError) {
  const HitDiff d = compare_hits(batch({{}, {}}), batch({{}}), 1e-4f);
  EXPECT_FALSE(d.ok());
  EXPECT_NE(d.first.find("batch sizes differ"), std::string::npos);
}

TEST(OcclusionCompare, CountsAndGrazing) {
  const std::vector<uint8_t> ref = {1, 0, 1, 0}, got = {1, 1, 0, 0};
  OcclusionDiff d = compare_occlusion(ref, got);
  EXPECT_EQ(d.differ, 2u);
  EXPECT_EQ(d.occluded_ref, 2u);
  EXPECT_EQ(d.occluded_got, 2u);
  EXPECT_NE(d.first.find("ray 1: ref clear, got occluded"), std::string::npos) << d.first;
  // ray 1: the candidate's blocker is grazing (u = 0); ray 2: the reference's blocker is interior.
  const HitBatch ref_hits = batch({{1.0f, 1, 0.3f, 0.3f}, {}, {1.0f, 2, 0.3f, 0.3f}, {}});
  const HitBatch got_hits = batch({{1.0f, 1, 0.3f, 0.3f}, {1.0f, 1, 0.0f, 0.3f}, {}, {}});
  HitCompareConfig cfg;
  cfg.allow_grazing = true;
  d = compare_occlusion(ref, got, cfg, &ref_hits, &got_hits);
  EXPECT_EQ(d.grazing, 1u);
  EXPECT_EQ(d.differ, 1u);
  EXPECT_NE(d.first.find("ray 2"), std::string::npos) << d.first;
  cfg.rel_tol = 0.0f;
  d = compare_occlusion(ref, got, cfg, &ref_hits, &got_hits);
  EXPECT_EQ(d.grazing, 0u);
  EXPECT_EQ(d.differ, 2u);
}


// With triangles, a contact is grazing when float arithmetic cannot decide it: tol = 4 ulps
// (2^-22) of the largest coordinate, in world units. Vertical rays below, so the edge
// measure is the in-plane distance.
struct GeometricJudge {
  std::vector<Triangle> tris = {
      {{32.0f, 0.0f, 0.0f}, {32.002f, 0.0f, 0.0f}, {32.0f, 0.002f, 0.0f}},  // 0: 0.002 wide, tol 7.6e-6
      {{0.0f, 0.0f, 0.0f}, {64.0f, 0.0f, 0.0f}, {0.0f, 64.0f, 0.0f}},      // 1: 64 wide, tol 1.5e-5
      {{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}, {2.0f, 2.0f, 2.0f}},        // 2: degenerate
      {{0.0f, 0.0f, -1.0f}, {64.0f, 0.0f, -1.0f}, {0.0f, 64.0f, -1.0f}},   // 3: 1 below 1
      {{0.0f, 0.0f, 1e-5f}, {64.0f, 0.0f, 1e-5f}, {0.0f, 64.0f, 1e-5f}},   // 4: 1e-5 above 1
      {{64.0f, 0.0f, 0.0f}, {64.0f, 64.0f, 0.0f}, {0.0f, 64.0f, 0.0f}},    // 5: 1's neighbour
      {{0.0f, 0.0f, 1e-4f}, {64.0f, 0.0f, 1e-4f}, {0.0f, 64.0f, 1e-4f}},   // 6: 1e-4 above 1
  };
  RayBatch rays;
  HitCompareConfig cfg;
  GeometricJudge() {
    cfg.rel_tol = 1e-4f;
    cfg.allow_grazing = true;
    cfg.rays = &rays;
    cfg.triangles = tris;
  }
  size_t add(Vec3 org, Vec3 dir, float tmin = 0.0f, float tmax = kInfinity) {
    rays.push_back({org, tmin, dir, tmax});
    return rays.size() - 1;
  }
  bool grazing(size_t ray, uint32_t prim, float t = 1.0f) const { return is_grazing({t, prim, 0.3f, 0.3f}, cfg, ray); }
};

TEST(HitCompareGeometry, ATinyTrianglesEdgeIsJudgedInWorldUnitsNotBarycentrics) {
  GeometricJudge g;
  const size_t edge = g.add({32.0005f, 5e-6f, 1.0f}, {0.0f, 0.0f, -1.0f});      // 5e-6 from y = 0
  const size_t inside = g.add({32.0008f, 1e-4f, 1.0f}, {0.0f, 0.0f, -1.0f});    // 1e-4 from y = 0
  EXPECT_TRUE(g.grazing(edge, 0));
  EXPECT_FALSE(g.grazing(inside, 0));
  // The hit's barycentrics (v = 0.0025) are far from edge_eps: without triangles it is an error.
  const HitBatch ref = batch({{1.0f, 0, 0.25f, 0.0025f}}), got = batch({{}});
  HitCompareConfig bary = g.cfg;
  bary.triangles = {};
  EXPECT_EQ(compare_hits(ref, got, bary).hit_miss, 1u);
  const HitDiff d = compare_hits(ref, got, g.cfg);
  EXPECT_EQ(d.grazing, 1u);
  EXPECT_TRUE(d.ok()) << d.first;
}

TEST(HitCompareGeometry, ALargeTrianglesEdgeGetsOnlyThePrecisionOfItsCoordinates) {
  GeometricJudge g;
  const size_t near = g.add({16.0f, 1e-5f, 1.0f}, {0.0f, 0.0f, -1.0f});  // 1e-5 < 1.5e-5 from y = 0
  const size_t far = g.add({16.0f, 4e-3f, 1.0f}, {0.0f, 0.0f, -1.0f});   // 4e-3: barycentric 6e-5 <= edge_eps
  EXPECT_TRUE(g.grazing(near, 1));
  EXPECT_FALSE(g.grazing(far, 1));
  const HitBatch ref = batch({{}, {1.0f, 1, 0.25f, 6.25e-5f}}), got = batch({{}, {}});
  HitCompareConfig bary = g.cfg;
  bary.triangles = {};
  EXPECT_TRUE(compare_hits(ref, got, bary).ok());  // excused by barycentrics
  const HitDiff d = compare_hits(ref, got, g.cfg);
  EXPECT_EQ(d.hit_miss, 1u);
  EXPECT_NE(d.first.find("ray 1: hit/miss"), std::string::npos) << d.first;
}

// The edge measure is the in-plane distance times the cosine of the incidence angle: a ray
// 1e-7 rad off the plane is undecidable 10 units inside; at 27 degrees off it is not.
TEST(HitCompareGeometry, ARayNearlyInThePlaneIsGrazingAndItsDistanceIllConditioned) {
  GeometricJudge g;
  const size_t flat = g.add({-10.0f, 16.0f, 2e-6f}, {1.0f, 0.0f, -1e-7f});  // meets z = 0 at (10, 16), t = 20
  const size_t steep = g.add({-10.0f, 16.0f, 20.0f}, {1.0f, 0.0f, -0.5f});  // at (30, 16), t = 40
  EXPECT_TRUE(g.grazing(flat, 1, 20.0f));
  EXPECT_FALSE(g.grazing(steep, 1, 40.0f));
  // The same triangle half a unit further along: 5e-8 off the plane for the flat ray (within
  // tol), 0.25 for the steep one.
  const HitBatch ref = batch({{20.0f, 1, 0.2f, 0.3f}, {40.0f, 1, 0.2f, 0.3f}});
  const HitBatch got = batch({{20.5f, 1, 0.2f, 0.3f}, {40.5f, 1, 0.2f, 0.3f}});
  const HitDiff d = compare_hits(ref, got, g.cfg);
  EXPECT_EQ(d.grazing, 1u);
  EXPECT_EQ(d.t_mismatch, 1u);
  EXPECT_NE(d.first.find("ray 1: distance"), std::string::npos) << d.first;
}

// Two triangles whose hit points lie within tol of each other's planes cannot be ordered in
// float, though their distances differ beyond rel_tol: a ray 0.1 degrees off z = 0 meets
// z = 0 and z = 1e-5 5e-3 apart (3.1e-4 of the world scale 16). 0.04 apart they are ordered.
TEST(HitCompareGeometry, HitsFloatCannotOrderAreExcusedOthersAreNot) {
  GeometricJudge g;
  const size_t ray = g.add({-10.0f, 16.0f, 0.04f}, {1.0f, 0.0f, -0.002f});  // z = 0 at t = 20, -0.04 at 40
  const float t_lifted = (0.04f - 1e-5f) / 0.002f;
  EXPECT_FALSE(g.grazing(ray, 1, 20.0f));
  EXPECT_FALSE(g.grazing(ray, 4, t_lifted));
  const HitBatch ref = batch({{20.0f, 1, 0.2f, 0.3f}});
  HitDiff d = compare_hits(ref, batch({{t_lifted, 4, 0.2f, 0.3f}}), g.cfg);
  EXPECT_EQ(d.ties, 0u);
  EXPECT_EQ(d.grazing, 1u);
  EXPECT_TRUE(d.ok()) << d.first;
  d = compare_hits(ref, batch({{40.0f, 3, 0.2f, 0.3f}}), g.cfg);  // passed z = 0 by
  EXPECT_EQ(d.other_prim, 1u);
  HitCompareConfig bary = g.cfg;
  bary.triangles = {};
  EXPECT_EQ(compare_hits(ref, batch({{t_lifted, 4, 0.2f, 0.3f}}), bary).other_prim, 1u);
}

// A different triangle within rel_tol is a tie only where float cannot order the two: across
// a shared edge, or 1e-5 above (tol 1.5e-5), judged from the triangles (the reported 1 + 5e-5
// is off both planes by more than tol). 1e-4 above, or off the ray (the tiny triangle 0), it
// is a different triangle; without triangles all four pass as ties.
TEST(HitCompareGeometry, OnlyTrueTiesAreTies) {
  GeometricJudge g;
  g.add({32.0f, 32.0f, 1.0f}, {0.0f, 0.0f, -1.0f});  // on the edge 1 and 5 share
  for (int i = 0; i < 3; ++i) g.add({16.0f, 16.0f, 1.0f}, {0.0f, 0.0f, -1.0f});
  const HitBatch ref = batch({{1.0f, 1, 0.5f, 0.5f}, {1.0f, 1, 0.25f, 0.25f}, {1.0f, 1, 0.25f, 0.25f},
                              {1.0f, 1, 0.25f, 0.25f}});
  const HitBatch got = batch({{1.0f, 5, 0.5f, 0.5f}, {1.0f + 5e-5f, 4, 0.25f, 0.25f},
                              {1.0f - 1e-4f, 6, 0.25f, 0.25f}, {1.0f, 0, 0.25f, 0.25f}});
  HitCompareConfig bary = g.cfg;
  bary.triangles = {};
  EXPECT_EQ(compare_hits(ref, got, bary).ties, 4u);
  const HitDiff d = compare_hits(ref, got, g.cfg);
  EXPECT_EQ(d.ties, 2u);
  EXPECT_EQ(d.grazing, 0u);
  EXPECT_EQ(d.other_prim, 2u);
  EXPECT_NE(d.first.find("ray 2: different triangle"), std::string::npos) << d.first;
}

// How far each side's hit points lie off their planes, in ulps of the largest coordinate (64:
// 1 ulp = 2^-18): t = 1 + 2^-17 is 2 ulps above triangle 1, t = 1 - 2^-16 4 ulps below.
TEST(HitCompareGeometry, PlaneOffsetsMeasureEachSidesDistances) {
  GeometricJudge g;
  for (int i = 0; i < 4; ++i) g.add({16.0f, 16.0f, 1.0f}, {0.0f, 0.0f, -1.0f});
  const HitBatch ref = batch({{1.0f, 1, 0.25f, 0.25f}, {1.0f, 1, 0.25f, 0.25f}, {1.0f, 1, 0.25f, 0.25f}, {}});
  const HitBatch got = batch({{1.0f, 1, 0.25f, 0.25f}, {1.0f + 0x1p-17f, 1, 0.25f, 0.25f},
                              {1.0f - 0x1p-16f, 1, 0.25f, 0.25f}, {}});
  const HitDiff d = compare_hits(ref, got, g.cfg);
  EXPECT_TRUE(d.ok()) << d.first;
  EXPECT_EQ(d.ref_offsets.hits, 3u);
  EXPECT_EQ(d.ref_offsets.max, 0.0);
  EXPECT_EQ(d.got_offsets.hits, 3u);
  EXPECT_DOUBLE_EQ(d.got_offsets.median, 2.0);
  EXPECT_DOUBLE_EQ(d.got_offsets.p99, 4.0);
  EXPECT_DOUBLE_EQ(d.got_offsets.max, 4.0);
  HitCompareConfig bary = g.cfg;
  bary.triangles = {};
  EXPECT_EQ(compare_hits(ref, got, bary).got_offsets.hits, 0u);
}

// An end of the segment within tol of the plane: a ray leaving the surface it starts on
// (tmin), or one ending on it (tmax). Away from the plane the same rays are decided.
TEST(HitCompareGeometry, ASegmentEndingOnThePlaneIsGrazing) {
  GeometricJudge g;
  const size_t leaving = g.add({10.0f, 10.0f, 0.0f}, {0.3f, 0.2f, 1.0f});
  const size_t ending = g.add({10.0f, 10.0f, 2.0f}, {0.0f, 0.0f, -1.0f}, 0.0f, 2.0f);
  const size_t through = g.add({10.0f, 10.0f, 2.0f}, {0.0f, 0.0f, -1.0f}, 0.0f, 3.0f);
  const size_t starting = g.add({10.0f, 10.0f, 2.0f}, {0.0f, 0.0f, -1.0f}, 2.0f);
  EXPECT_TRUE(g.grazing(leaving, 1, 0.0f));
  EXPECT_TRUE(g.grazing(ending, 1, 2.0f));
  EXPECT_FALSE(g.grazing(through, 1, 2.0f));
  EXPECT_TRUE(g.grazing(starting, 1, 2.0f));
}

// The excuse needs the ray to meet the claimed triangle (edges grown by tol): a ray along the
// line of an edge, 36 units past its end, or one starting on the plane far outside the triangle
// is not a contact float cannot decide, whatever a tracer claims there.
TEST(HitCompareGeometry, AClaimedContactOffTheTriangleIsNoExcuse) {
  GeometricJudge g;
  const size_t past_edge = g.add({100.0f, 0.0f, 1.0f}, {0.0f, 0.0f, -1.0f});  // on the line y = 0
  const size_t on_edge = g.add({32.0f, 0.0f, 1.0f}, {0.0f, 0.0f, -1.0f});
  const size_t off_plane = g.add({100.0f, 100.0f, 0.0f}, {0.3f, 0.2f, 1.0f});
  EXPECT_FALSE(g.grazing(past_edge, 1));
  EXPECT_TRUE(g.grazing(on_edge, 1));
  EXPECT_FALSE(g.grazing(off_plane, 1, 0.0f));
  const HitBatch claims = batch({{1.0f, 1, 0.0f, 0.0f}, {1.0f, 1, 0.5f, 0.0f}, {0.0f, 1, 0.0f, 0.0f}});
  const HitDiff d = compare_hits(batch({{}, {}, {}}), claims, g.cfg);
  EXPECT_EQ(d.hit_miss, 2u);
  EXPECT_EQ(d.grazing, 1u);
}

// No excuse without a contact to judge: a degenerate triangle (a segment) is undecidable where
// the ray meets it and only there, and a triangle id the scene lacks, a zero or NaN direction
// are not grazing, and a miss is none.
TEST(HitCompareGeometry, DegenerateInputs) {
  GeometricJudge g;
  const size_t ok = g.add({10.0f, 10.0f, 2.0f}, {0.0f, 0.0f, -1.0f});  // over the line x = y = z
  const size_t beside = g.add({10.0f, 5.0f, 2.0f}, {0.0f, 0.0f, -1.0f});
  EXPECT_FALSE(g.grazing(beside, 2));
  const size_t zero = g.add({10.0f, 10.0f, 2.0f}, {0.0f, 0.0f, 0.0f});
  const size_t nan = g.add({10.0f, 10.0f, 2.0f}, {std::nanf(""), 0.0f, -1.0f});
  EXPECT_TRUE(g.grazing(ok, 2));
  EXPECT_FALSE(g.grazing(ok, 1));
  EXPECT_FALSE(g.grazing(ok, 99));
  EXPECT_FALSE(g.grazing(zero, 1));
  EXPECT_FALSE(g.grazing(nan, 1));
  EXPECT_FALSE(g.grazing(7, 1));  // no such ray
  EXPECT_FALSE(is_grazing({}, g.cfg, ok));
}

// compare_occlusion asks the same question of the occluded side's closest hit.
TEST(HitCompareGeometry, OcclusionExcusesOnlyAnUndecidableBlocker) {
  GeometricJudge g;
  g.add({32.0005f, 5e-6f, 1.0f}, {0.0f, 0.0f, -1.0f});  // the tiny triangle's edge
  g.add({16.0f, 4e-3f, 1.0f}, {0.0f, 0.0f, -1.0f});     // the large one, decided
  const HitBatch blockers = batch({{1.0f, 0, 0.25f, 0.0025f}, {1.0f, 1, 0.25f, 6.25e-5f}});
  const HitBatch none = batch({{}, {}});
  const OcclusionDiff d = compare_occlusion({1, 1}, {0, 0}, g.cfg, &blockers, &none);
  EXPECT_EQ(d.grazing, 1u);
  EXPECT_EQ(d.differ, 1u);
  EXPECT_NE(d.first.find("ray 1"), std::string::npos) << d.first;
}

}  // namespace
}  // namespace rayscout
