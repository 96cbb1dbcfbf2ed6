// The Embree peer: options, build info, tmin/tmax, packets, and agreement with bvh on a real scene.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>

#include "generated_scenes.h"
#include "rayscout/accelerators.h"
#include "rayscout/core/hit_compare.h"
#include "rayscout/core/scenes_dir.h"
#include "rayscout/embree/embree_accelerator.h"
#include "rayscout/render/workloads.h"
#include "rayscout/scene/load_scene.h"

namespace rayscout {
namespace {

using testing::small_scale;

bool registered(const std::string& name) {
  const auto& all = accelerators();
  return std::any_of(all.begin(), all.end(), [&](const AcceleratorInfo& a) { return a.name == name; });
}

TEST(Embree, BuildInfoReportsTimeAndMemory) {
  const auto tris = testing::random_soup(5000, 3);
  const EmbreeAccelerator accel(tris);
  EXPECT_EQ(accel.name(), "embree");
  EXPECT_GT(accel.build_info().build_ms, 0.0);
  // Embree's BVH over 5000 triangles needs far more than 10 kB and far less than 100 MB.
  EXPECT_GT(accel.build_info().memory_bytes, 10'000u);
  EXPECT_LT(accel.build_info().memory_bytes, 100'000'000u);
}

TEST(Embree, TminAndTmaxAreHonoured) {
  // Two parallel squares at z = 1 (ids 0, 1) and z = 2 (ids 2, 3); rays along +z from z = 0.
  std::vector<Triangle> tris;
  for (float z : {1.0f, 2.0f}) {
    tris.push_back({{-1, -1, z}, {1, -1, z}, {1, 1, z}});
    tris.push_back({{-1, -1, z}, {1, 1, z}, {-1, 1, z}});
  }
  const EmbreeAccelerator accel(tris);
  RayBatch rays;
  rays.push_back({{0.3f, -0.2f, 0}, 0.0f, {0, 0, 1}, kInfinity});  // first plane
  rays.push_back({{0.3f, -0.2f, 0}, 1.5f, {0, 0, 1}, kInfinity});  // tmin skips the first
  rays.push_back({{0.3f, -0.2f, 0}, 0.0f, {0, 0, 1}, 0.5f});       // tmax stops before both
  rays.push_back({{0.3f, -0.2f, 0}, 2.5f, {0, 0, 1}, kInfinity});  // tmin beyond both
  rays.push_back({{0.3f, -0.2f, 0}, 0.0f, {0, 0, 2}, kInfinity});  // unnormalised: t = 0.5
  HitBatch hits;
  accel.intersect(rays, hits);
  EXPECT_FLOAT_EQ(hits.t[0], 1.0f);
  EXPECT_EQ(hits.prim[0], 0u);  // (0.3, -0.2) lies in the first triangle of each square
  EXPECT_FLOAT_EQ(hits.t[1], 2.0f);
  EXPECT_EQ(hits.prim[1], 2u);
  EXPECT_EQ(hits.prim[2], kInvalidId);
  EXPECT_EQ(hits.t[2], kInfinity);
  EXPECT_EQ(hits.prim[3], kInvalidId);
  EXPECT_FLOAT_EQ(hits.t[4], 0.5f);
  // Barycentrics as ours: point = (1-u-v) v0 + u v1 + v v2.
  const Triangle& t = tris[0];
  const Vec3 p = t.v0 * (1 - hits.u[0] - hits.v[0]) + t.v1 * hits.u[0] + t.v2 * hits.v[0];
  EXPECT_NEAR(p.x, 0.3f, 1e-6f);
  EXPECT_NEAR(p.y, -0.2f, 1e-6f);
  std::vector<uint8_t> occ;
  accel.occluded(rays, occ);
  EXPECT_EQ(occ, (std::vector<uint8_t>{1, 1, 0, 0, 1}));
}

TEST(Embree, EmptySceneMissesEverything) {
  const EmbreeAccelerator accel(std::span<const Triangle>{});
  const RayBatch rays = testing::random_rays(100, 1);
  HitBatch hits;
  std::vector<uint8_t> occ;
  accel.intersect(rays, hits);
  accel.occluded(rays, occ);
  EXPECT_EQ(std::count(hits.prim.begin(), hits.prim.end(), kInvalidId), 100);
  EXPECT_EQ(std::count(occ.begin(), occ.end(), 0), 100);
}

TEST(Embree, PacketsOf16GiveTheSameResultAsSingleRays) {
  const Scene scene = testing::scene_from_triangles(testing::random_soup(3000, 8));
  const RayBatch rays = testing::random_rays(1001, 9);  // not a multiple of 16
  AcceleratorOptions single, packet;
  packet.set("packet=16");
  HitBatch a, b;
  std::vector<uint8_t> oa, ob;
  make_accelerator("embree", scene, single)->intersect(rays, a);
  const auto p = make_accelerator("embree", scene, packet);
  p->intersect(rays, b);
  make_accelerator("embree", scene, single)->occluded(rays, oa);
  p->occluded(rays, ob);
  EXPECT_EQ(a.t, b.t);
  EXPECT_EQ(a.prim, b.prim);
  EXPECT_EQ(oa, ob);
  EXPECT_GT(std::count(oa.begin(), oa.end(), 1), 100);
}

TEST(Embree, NoCountersOnlyRays) {
  const Scene scene = testing::scene_from_triangles(testing::grid(8));
  const RayBatch rays = testing::random_rays(50, 2);
  TraceStats stats;
  HitBatch hits;
  make_accelerator("embree", scene)->intersect(rays, hits, &stats);
  EXPECT_EQ(stats.rays, 50u);
  EXPECT_EQ(stats.ray_box_tests + stats.ray_tri_tests + stats.traversal_steps, 0u);
}

TEST(Embree, BadOptionsAreInputErrors) {
  const Scene scene = testing::scene_from_triangles(testing::grid(2));
  for (const char* kv : {"packet=4", "quality=low", "robust=maybe", "speed=11"}) {
    AcceleratorOptions o;
    o.set(kv);
    EXPECT_THROW(make_accelerator("embree", scene, o), InputError) << kv;
  }
}

TEST(Embree, NonRobustModeStillAgreesOnOrdinaryRays) {
  const Scene scene = testing::scene_from_triangles(testing::random_soup(3000, 4));
  const RayBatch rays = testing::random_rays(3000, 5);
  AcceleratorOptions fast;
  fast.set("robust=off");
  HitBatch ref, got;
  BruteForce(scene.triangles).intersect(rays, ref);
  make_accelerator("embree", scene, fast)->intersect(rays, got);
  HitCompareConfig cfg;
  cfg.rel_tol = 1e-4f;
  cfg.allow_grazing = true;
  const HitDiff d = compare_hits(ref, got, cfg);
  EXPECT_TRUE(d.ok()) << d.first;
}

// A real scene (Sibenik, else Sponza): embree and bvh agree ray by ray within 1e-4, with no
// hit/miss disagreement except at grazing contacts, on random rays and primary rays.
TEST(EmbreeVsBvh, RealScene) {
  if (!registered("bvh")) GTEST_SKIP() << "the 'bvh' accelerator is not registered in this build";
  auto file = find_scene_file("sibenik/sibenik.obj");
  if (!file) file = find_scene_file("crytek-sponza/sponza.obj");
  if (!file) GTEST_SKIP() << "neither sibenik/sibenik.obj nor crytek-sponza/sponza.obj under " << scenes_dir()
                          << " (set RAYSCOUT_SCENES)";
  const Scene scene = load_scene(*file);
  const auto bvh = make_accelerator("bvh", scene);
  const auto embree = make_accelerator("embree", scene);

  const int res = small_scale() ? 64 : 256;
  RayBatch random;
  const Bounds3 b = scene.bounds();
  std::mt19937 rng(42);
  std::uniform_real_distribution<float> u(0.0f, 1.0f), s(-1.0f, 1.0f);
  for (int i = 0; i < res * res; ++i) {
    const Vec3 o = b.lo + b.diagonal() * Vec3(u(rng), u(rng), u(rng));
    random.push_back({o, 0.0f, Vec3(s(rng), s(rng), s(rng)), kInfinity});
  }
  const RayBatch primary = make_workload(scene, *bvh, Workload::Primary, {.width = res, .height = res});

  HitCompareConfig cfg;
  cfg.rel_tol = 1e-4f;
  cfg.allow_grazing = true;
  for (const auto& [name, rays] : {std::pair<const char*, const RayBatch&>{"random", random}, {"primary", primary}}) {
    HitBatch hb, he;
    bvh->intersect(rays, hb);
    embree->intersect(rays, he);
    const HitDiff d = compare_hits(hb, he, cfg);
    EXPECT_TRUE(d.ok()) << name << ": " << d.hit_miss << " hit/miss, " << d.other_prim << " other triangle, "
                        << d.t_mismatch << " distance; first: " << d.first;
    EXPECT_GT(d.both_hit, rays.size() / 10) << name;
    EXPECT_LE(d.grazing, rays.size() / 1000) << name;
    EXPECT_LT(d.p99_rel_diff, 1e-5) << name;

    std::vector<uint8_t> ob, oe;
    bvh->occluded(rays, ob);
    embree->occluded(rays, oe);
    const OcclusionDiff od = compare_occlusion(ob, oe, cfg, &hb, &he);
    EXPECT_TRUE(od.ok()) << name << ": " << od.first;
  }
}

}  // namespace
}  // namespace rayscout
