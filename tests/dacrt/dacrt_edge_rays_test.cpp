// Edge cases of DACRT's ray filtering against brute force: negative tmin (hits behind the
// origin, every box's far distance negative), tmin == tmax, rays starting on a triangle or a
// box face, degenerate triangles.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "box_kernels.h"
#include "dacrt_rays.h"
#include "generated_scenes.h"
#include "rayscout/accelerators.h"
#include "rayscout/core/hit_compare.h"
#include "rayscout/dacrt/dacrt.h"

namespace rayscout {
namespace {

using testing::TestMesh;

// Every DACRT flavour: both methods, and the full method sampling deep down with few rays.
const std::vector<std::pair<const char*, std::vector<std::string>>> kFlavours = {
    {"dacrt", {"parallel=off"}},
    {"dacrt-rs", {"parallel=off"}},
    {"dacrt-rs", {"min_rays=64", "samples=16", "sample_budget=0", "parallel=off"}},
    {"dacrt-rs", {"min_rays=64", "samples=16", "delta_r=1", "delta_t=2", "bins=2", "parallel=off"}},
};

void expect_brute_force_hits(const Scene& scene, const RayBatch& rays, const std::string& what) {
  const auto [ref, ref_occ] = testing::brute_force(scene.triangles, rays);
  size_t hits = 0;
  for (uint32_t p : ref.prim) hits += p != kInvalidId;
  EXPECT_GT(hits, 0u) << what << ": the rays should hit something";
  for (const auto& [name, opts] : kFlavours) {
    const auto accel = make_accelerator(name, scene, testing::options_of(opts));
    HitBatch got;
    std::vector<uint8_t> occ;
    accel->intersect(rays, got);
    accel->occluded(rays, occ);
    const HitDiff d = compare_hits(ref, got, 0.0f);
    EXPECT_TRUE(d.ok()) << what << ", " << name << " " << testing::label_of(opts) << ": " << d.hit_miss
                        << " hit/miss, " << d.other_prim << " other triangle; first " << d.first;
    size_t differ = 0;
    for (size_t i = 0; i < occ.size(); ++i) differ += occ[i] != ref_occ[i];
    EXPECT_EQ(differ, 0u) << what << ", " << name << " " << testing::label_of(opts) << " occluded";
  }
}

class DacrtEdgeRays : public ::testing::TestWithParam<TestMesh> {};

TEST_P(DacrtEdgeRays, NegativeTminMatchesBruteForce) {
  const Scene scene = testing::scene_from_triangles(GetParam().triangles);
  const RayBatch nasty = testing::nasty_rays(scene.triangles, 31);
  RayBatch ahead, reversed, segment;
  for (size_t i = 0; i < nasty.size(); ++i) {
    const Ray r = nasty[i];
    if (!(max_component(abs(r.dir)) > 0.0f) || !is_finite(r.dir)) continue;
    // The origin moved 4 units on along the ray: its hits now lie behind it.
    const float s = 4.0f / length(r.dir);
    ahead.push_back({r.org + r.dir * s, i % 2 ? -kInfinity : -s - 1.0f, r.dir, i % 3 ? kInfinity : 0.5f});
    // The ray turned round, hits only behind the origin (closest = most negative t).
    reversed.push_back({r.org, -kInfinity, -r.dir, 0.0f});
    // A segment around the origin.
    segment.push_back({r.org, -0.3f, r.dir, 0.3f});
  }
  expect_brute_force_hits(scene, ahead, "origin moved ahead");
  expect_brute_force_hits(scene, reversed, "reversed");
  expect_brute_force_hits(scene, segment, "segment around the origin");
}

// A ray with tmin < 0 reaching a flat box (triangles in one axis plane) behind its origin:
// the slab test's far distance is negative there, and core's scale 1 + 2 gamma(3) moves it
// away from zero, below the near distance, so core's intersect_box culls the box (its doc:
// conservative for t >= 0 only). DACRT filters with boxes grown by pad_for(magnitude),
// 2^-19 or more of any slab distance, far beyond the scale's 2 gamma(3) ~ 3.6e-7, and keeps it.
TEST(DacrtEdgeRays, FlatBoxBehindTheOriginIsKept) {
  const Bounds3 flat{{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 0.0f}};
  const Vec3 org{0.3f, 0.6f, 0.5f}, inv{kInfinity, kInfinity, 1.0f};  // direction (0, 0, 1)
  float tnear = 0.0f;
  EXPECT_FALSE(intersect_box(org, inv, flat, -1.0f, kInfinity, tnear)) << "core's test, unpadded";
  EXPECT_TRUE(intersect_box(Vec3(org.x, org.y, -org.z), inv, flat, -1.0f, kInfinity, tnear)) << "the same box ahead is kept";
  const dacrt::RayRecord r{org.x, org.y, org.z, -1.0f, inv.x, inv.y, inv.z, kInfinity};
  EXPECT_TRUE(dacrt::ray_hits_box(r, dacrt::padded(flat, dacrt::pad_for(1.0f)), tnear)) << "DACRT's filter";

  // The same through the whole recursion: rays along +z (zero, negative-zero and unnormalised
  // x, y components) from above a grid on z = 0, whose nodes' boxes are all flat, hitting it
  // at t < 0; and rays starting on the grid (t = 0), tmin == tmax.
  const Scene scene = testing::scene_from_triangles(testing::grid(32));
  testing::Rng rng(41);
  RayBatch rays;
  for (int i = 0; i < 4000; ++i) {
    const Vec3 o{rng.uniform(), rng.uniform(), i % 4 == 3 ? 0.0f : rng.uniform(0.1f, 2.0f)};
    const float zero = i % 2 ? -0.0f : 0.0f, len = i % 3 == 0 ? 1.0f : 3.0f;
    const float tmin = i % 5 == 0 ? -kInfinity : -o.z / len;  // exactly at the grid, or beyond
    rays.push_back({o, tmin, {zero, -zero, len}, i % 7 == 0 ? tmin : kInfinity});
  }
  expect_brute_force_hits(scene, rays, "grid behind the origin");
}

// Hits at an infinite distance: a short direction (2^-32, the shortest Accelerator::intersect
// traces unscaled) overflows t for triangles 1e30 away, to -inf behind the origin (tmin = -inf)
// and +inf ahead. Brute force keeps
// such hits (tmin <= t <= tmax) and breaks their ties by the smaller id like any other. Here
// 64 triangles of one plane with one centroid, each twice (ids i and i + 64), are split by
// position, so tied triangles meet in different nodes: a ray whose t is already -inf must still
// enter the other node (its filter tmax was -inf + inf = NaN, which culled every box). Any hit
// too, with tmax = -inf (the only hit at -inf) and tmin = tmax = +inf (only at +inf).
TEST(DacrtEdgeRays, HitsAtInfiniteDistancesMatchBruteForce) {
  std::vector<Triangle> tris;
  testing::Rng rng(5);
  const Vec3 c{0.5f, 0.5f, 1e30f};
  for (int i = 0; i < 64; ++i) {
    Vec3 a = rng.direction() * 0.4f, b = rng.direction() * 0.4f;
    a.z = b.z = 0.0f;
    tris.push_back({c + a, c + b, c - a - b});
  }
  for (size_t i = 0; i < 64; ++i) tris.push_back(tris[i]);
  const Scene scene = testing::scene_from_triangles(tris);
  RayBatch rays;
  for (int i = 0; i < 2000; ++i) {
    const float dz = i % 2 ? 0x1p-32f : -0x1p-32f;
    const float tmin = i % 4 == 3 ? kInfinity : -kInfinity, tmax = i % 8 == 2 ? -kInfinity : kInfinity;
    rays.push_back({{rng.uniform(0.3f, 0.7f), rng.uniform(0.3f, 0.7f), 0.0f}, tmin, {0.0f, 0.0f, dz}, tmax});
  }
  const auto [ref, ref_occ] = testing::brute_force(scene.triangles, rays);
  size_t at_minus_inf = 0, at_plus_inf = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    if (ref.prim[i] == kInvalidId) continue;
    at_minus_inf += ref.t[i] == -kInfinity;
    at_plus_inf += ref.t[i] == kInfinity;
  }
  EXPECT_GT(at_minus_inf, 500u);
  EXPECT_GT(at_plus_inf, 500u);
  expect_brute_force_hits(scene, rays, "hits at +-inf");
}

// Finite box distances: triangles 1e10 wide, 1e10 away, a direction 2^-30 long. The true t
// (~1e19) and every box distance are finite. Woop's interpolated t overflowed its numerator
// here, to -inf behind the origin (+inf ahead), so that a first hit at -inf must not cull the
// other nodes; the plane distance, clamped to the vertices' depths (core's plane_distance),
// stays finite, so tied triangles (64 shapes around one centre, each twice: ids i and i + 64)
// tie at a finite t and the smallest id wins. Segments [-inf, +inf] and [0, +inf] hit;
// [-inf, -inf] and [+inf, +inf] contain no finite t and miss.
TEST(DacrtEdgeRays, HitsInFarFiniteBoxesMatchBruteForce) {
  std::vector<Triangle> tris;
  testing::Rng rng(7);
  const Vec3 c{0.0f, 0.0f, -1e10f};
  for (int i = 0; i < 64; ++i) {
    Vec3 a = rng.direction() * (1e10f * rng.uniform(1.0f, 2.0f)), b = rng.direction() * (1e10f * rng.uniform(1.0f, 2.0f));
    a.z = b.z = 0.0f;
    tris.push_back({c + a, c + b, c - a - b});
  }
  for (size_t i = 0; i < 64; ++i) tris.push_back(tris[i]);
  const Scene scene = testing::scene_from_triangles(tris);
  RayBatch rays;
  for (int i = 0; i < 4000; ++i) {
    const Vec3 o{rng.uniform(-0.01f, 0.01f), rng.uniform(-0.01f, 0.01f), 0.0f};
    switch (i % 4) {
      case 0: rays.push_back({o, -kInfinity, {0.0f, 0.0f, 0x1p-30f}, kInfinity}); break;
      case 1: rays.push_back({o, -kInfinity, {0.0f, 0.0f, 0x1p-30f}, -kInfinity}); break;
      case 2: rays.push_back({o, kInfinity, {0.0f, 0.0f, -0x1p-30f}, kInfinity}); break;
      default: rays.push_back({o, 0.0f, {0.0f, 0.0f, -0x1p-30f}, kInfinity}); break;
    }
  }
  const auto [ref, ref_occ] = testing::brute_force(scene.triangles, rays);
  for (size_t i = 0; i < rays.size(); ++i) {
    if (i % 4 == 1 || i % 4 == 2) {
      ASSERT_EQ(ref.prim[i], kInvalidId) << "ray " << i << ": a segment at infinity misses";
    } else {
      ASSERT_NE(ref.prim[i], kInvalidId) << "ray " << i << ": the test needs a hit";
      ASSERT_TRUE(std::isfinite(ref.t[i]) && std::fabs(ref.t[i]) > 1e18f) << "ray " << i << ": t " << ref.t[i];
    }
  }
  expect_brute_force_hits(scene, rays, "hits in far finite boxes");
}

// No triangles (the scene loader refuses such scenes; a library caller may not): every ray
// misses, as for brute force, and the call takes no scratch memory.
TEST(DacrtEdgeRays, NoTrianglesMissEverything) {
  const std::vector<Triangle> none;
  const RayBatch rays = testing::random_rays(100, 3);
  const auto [ref, ref_occ] = testing::brute_force(none, rays);
  for (const DacrtConfig& config : {DacrtConfig::afra(), DacrtConfig::ray_sampled()}) {
    const DacrtAccelerator dacrt(none, config);
    HitBatch got;
    std::vector<uint8_t> occ;
    dacrt.intersect(rays, got);
    EXPECT_TRUE(compare_hits(ref, got, 0.0f).ok());
    dacrt.occluded(rays, occ);
    EXPECT_EQ(occ, ref_occ);
    EXPECT_EQ(dacrt.last_trace_memory_bytes(), 0u);
  }
}

// Degenerate triangles (a point, two equal vertices, three collinear ones; zero-volume boxes,
// det = 0 for every ray) among ordinary ones, and rays aimed at them: the hits of brute force.
TEST(DacrtEdgeRays, DegenerateTrianglesMatchBruteForce) {
  std::vector<Triangle> tris = testing::random_soup(300, 9);
  testing::Rng rng(3);
  for (int i = 0; i < 300; ++i) {
    const Vec3 a = rng.point(0.0f, 1.0f), b = rng.point(0.0f, 1.0f);
    if (i % 3 == 0) tris.push_back({a, a, a});
    else if (i % 3 == 1) tris.push_back({a, b, a});
    else tris.push_back({a, (a + b) * 0.5f, b});
  }
  const Scene scene = testing::scene_from_triangles(tris);
  RayBatch rays = testing::nasty_rays(scene.triangles, 43);
  for (size_t i = 300; i < tris.size(); ++i) {
    const Vec3 o = rng.point(-0.5f, 1.5f);
    rays.push_back({o, 0.0f, tris[i].v1 - o, kInfinity});
  }
  expect_brute_force_hits(scene, rays, "degenerate triangles");
}

// A ray with an infinite origin coordinate misses (Accelerator::intersect gives it a NaN
// direction and keeps its origin). It must not set the box padding: pad_for(inf) grew every
// box to infinity, and one such ray made the whole batch test every ray against every
// triangle. Its batch does the work of the same batch with a NaN origin there instead (never
// counted in the padding; the ray itself is left out of the trace, see RaysThatMustMissCostNothing).
TEST(DacrtEdgeRays, AnInfiniteOriginDoesNotDisableFiltering) {
  const Scene scene = testing::scene_from_triangles(testing::spheres_on_floor());
  const RayBatch plain = testing::pinhole_rays(testing::kInsideEye, testing::kInsideLook, 60.0f, 64, 64);
  auto with_origin = [&](float x) {
    RayBatch rays = plain;
    rays.push_back({{x, 1.0f, 0.0f}, 0.0f, {1.0f, 0.0f, 0.0f}, kInfinity});
    return rays;
  };
  const RayBatch nan_origin = with_origin(std::numeric_limits<float>::quiet_NaN());
  const auto [ref, ref_occ] = testing::brute_force(scene.triangles, nan_origin);
  for (const float bad : {kInfinity, -kInfinity}) {
    const RayBatch rays = with_origin(bad);
    for (const char* name : {"dacrt", "dacrt-rs"}) {
      const auto accel = make_accelerator(name, scene);
      TraceStats want, got;
      HitBatch want_hits, got_hits;
      accel->intersect(nan_origin, want_hits, &want);
      accel->intersect(rays, got_hits, &got);
      EXPECT_TRUE(compare_hits(ref, got_hits, 0.0f).ok()) << name;
      EXPECT_EQ(got.ray_tri_tests, want.ray_tri_tests) << name << ", origin " << bad;
      EXPECT_EQ(got.ray_box_tests, want.ray_box_tests) << name << ", origin " << bad;
    }
  }
}

// Rays that must miss (an infinite or NaN direction component or origin coordinate:
// Accelerator::intersect traces them with a NaN direction, which passes every box test; an
// empty or NaN segment, [+inf, 5] and [0, -inf] of which pass every box by filter_tmin and
// filter_tmax) cost nothing: a batch with such rays among ordinary ones does exactly the work
// of the ordinary rays alone, and they miss. (They were tested against every triangle.)
TEST(DacrtEdgeRays, RaysThatMustMissCostNothing) {
  const Scene scene = testing::scene_from_triangles(testing::spheres_on_floor());
  const RayBatch plain = testing::pinhole_rays(testing::kInsideEye, testing::kInsideLook, 60.0f, 64, 64);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = kInfinity;
  const std::vector<Ray> bad = {
      {{0.0f, 1.0f, 0.0f}, 0.0f, {nan, 1.0f, 0.0f}, inf},   {{0.0f, 1.0f, 0.0f}, 0.0f, {inf, 0.0f, 0.0f}, inf},
      {{nan, 1.0f, 0.0f}, 0.0f, {1.0f, 0.0f, 0.0f}, inf},   {{0.0f, -inf, 0.0f}, 0.0f, {0.0f, 1.0f, 0.0f}, inf},
      {{0.0f, 1.0f, 0.0f}, -inf, {-inf, inf, nan}, inf},
      {{0.0f, 1.0f, 0.0f}, inf, {1.0f, 0.0f, 0.0f}, 5.0f},  {{0.0f, 1.0f, 0.0f}, 0.0f, {1.0f, 0.0f, 0.0f}, -inf},
      {{0.0f, 1.0f, 0.0f}, 2.0f, {1.0f, 0.0f, 0.0f}, 1.0f}, {{0.0f, 1.0f, 0.0f}, nan, {1.0f, 0.0f, 0.0f}, inf},
      {{0.0f, 1.0f, 0.0f}, 0.0f, {1.0f, 0.0f, 0.0f}, nan},
  };
  RayBatch mixed;  // a bad ray after every 500th ordinary one, and two at the end
  for (size_t i = 0; i < plain.size(); ++i) {
    mixed.push_back(plain[i]);
    if (i % 500 == 0) mixed.push_back(bad[i / 500 % bad.size()]);
  }
  for (const Ray& r : {bad[0], bad[1]}) mixed.push_back(r);
  for (const auto& [name, opts] : kFlavours) {
    const auto accel = make_accelerator(name, scene, testing::options_of(opts));
    TraceStats want, got, want_occ, got_occ;
    HitBatch want_hits, got_hits;
    std::vector<uint8_t> want_o, got_o;
    accel->intersect(plain, want_hits, &want);
    accel->intersect(mixed, got_hits, &got);
    accel->occluded(plain, want_o, &want_occ);
    accel->occluded(mixed, got_o, &got_occ);
    EXPECT_EQ(got.ray_tri_tests, want.ray_tri_tests) << name;
    EXPECT_EQ(got.ray_box_tests, want.ray_box_tests) << name;
    EXPECT_EQ(got.traversal_steps, want.traversal_steps) << name;
    EXPECT_EQ(got_occ.ray_tri_tests, want_occ.ray_tri_tests) << name;
    EXPECT_EQ(got_occ.ray_box_tests, want_occ.ray_box_tests) << name;
    size_t j = 0;
    for (size_t i = 0; i < mixed.size(); ++i) {
      const bool is_bad = !is_finite(mixed[i].org) || !is_finite(mixed[i].dir) || !(mixed[i].tmin <= mixed[i].tmax);
      if (is_bad) {
        EXPECT_EQ(got_hits.prim[i], kInvalidId) << name << " ray " << i;
        EXPECT_EQ(got_o[i], 0) << name << " ray " << i;
        continue;
      }
      EXPECT_EQ(got_hits.prim[i], want_hits.prim[j]) << name << " ray " << i;
      EXPECT_EQ(got_hits.t[i], want_hits.t[j]) << name << " ray " << i;
      EXPECT_EQ(got_o[i], want_o[j]) << name << " ray " << i;
      ++j;
    }
    EXPECT_EQ(j, plain.size());
  }
}

INSTANTIATE_TEST_SUITE_P(Nasty, DacrtEdgeRays, ::testing::ValuesIn(testing::nasty_meshes()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace rayscout
