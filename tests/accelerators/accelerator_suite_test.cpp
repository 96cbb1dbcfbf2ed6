// The one suite every accelerator runs: ray by ray against brute force on the nasty meshes.
#include <gtest/gtest.h>

#include "generated_scenes.h"
#include "rayscout/accelerators.h"
#include "rayscout/core/hit_compare.h"

namespace rayscout {
namespace {

using testing::TestMesh;

struct SuiteParam {
  std::string accel;
  TestMesh mesh;
  friend void PrintTo(const SuiteParam& p, std::ostream* os) { *os << p.accel << " on " << p.mesh.name; }
};

std::vector<SuiteParam> all_params() {
  std::vector<SuiteParam> params;
  for (const auto& a : accelerators())
    for (auto& m : testing::nasty_meshes()) params.push_back({a.name, m});
  return params;
}

class AcceleratorSuite : public ::testing::TestWithParam<SuiteParam> {};

// How closely an accelerator must agree with brute force.
struct Tolerance {
  HitCompareConfig cfg;
  size_t max_errors = 0;  ///< disagreements allowed beyond ties and grazing contacts
};

// Bit-identical for our accelerators (one kernel). Embree computes t its own way: within 1e-4
// relative, ties and grazing contacts allowed. Slivers of aspect 1e4 turn 1e-7 rounding of the
// hit point into 1e-3 in a barycentric, and Embree's sliver normal (a cross product of nearly
// parallel edges) is off by ~1e-3, so there up to 1% of the rays may disagree.
Tolerance tolerance_for(const std::string& accel, const std::string& mesh, size_t rays) {
  Tolerance tol;
  tol.cfg.rel_tol = 0.0f;
  if (accel == "embree") {
    tol.cfg.rel_tol = 1e-4f;
    tol.cfg.allow_grazing = true;
    tol.cfg.edge_eps = 1e-3f;
    if (mesh == "slivers") tol.max_errors = rays / 100;
  }
  return tol;
}

TEST_P(AcceleratorSuite, ClosestHitsMatchBruteForce) {
  const auto& p = GetParam();
  const Scene scene = testing::scene_from_triangles(p.mesh.triangles);
  const RayBatch rays = testing::nasty_rays(scene.triangles, 7);
  HitBatch ref, got;
  BruteForce(scene.triangles).intersect(rays, ref);
  make_accelerator(p.accel, scene)->intersect(rays, got);
  // Same kernel everywhere: bit-identical t. Embree has its own triangle test: t within 1e-4
  // relative, a different triangle only at a true tie, and hit/miss only at grazing contacts
  // (rays aimed exactly at boundary edges and vertices, rays leaving the surface they start on).
  const Tolerance tol = tolerance_for(p.accel, p.mesh.name, rays.size());
  const HitDiff d = compare_hits(ref, got, tol.cfg);
  EXPECT_LE(d.grazing, rays.size() / 5) << "grazing disagreements should be rare";
  EXPECT_LE(d.hit_miss + d.other_prim + d.t_mismatch, tol.max_errors)
      << d.hit_miss << " hit/miss, " << d.other_prim << " other triangle, " << d.t_mismatch
      << " distance; first: " << d.first;
  size_t hits = 0;
  for (uint32_t prim : ref.prim) hits += prim != kInvalidId;
  EXPECT_GT(hits, rays.size() / 20) << "the ray set should hit something";
}

TEST_P(AcceleratorSuite, OcclusionMatchesBruteForce) {
  const auto& p = GetParam();
  const Scene scene = testing::scene_from_triangles(p.mesh.triangles);
  const RayBatch rays = testing::nasty_rays(scene.triangles, 11);
  std::vector<uint8_t> ref, got;
  BruteForce(scene.triangles).occluded(rays, ref);
  make_accelerator(p.accel, scene)->occluded(rays, got);
  ASSERT_EQ(ref.size(), got.size());
  const Tolerance tol = tolerance_for(p.accel, p.mesh.name, rays.size());
  HitBatch ref_hits, got_hits;  // closest hits tell whether a disagreement is at a grazing contact
  if (tol.cfg.allow_grazing) {
    BruteForce(scene.triangles).intersect(rays, ref_hits);
    make_accelerator(p.accel, scene)->intersect(rays, got_hits);
  }
  const OcclusionDiff d = compare_occlusion(ref, got, tol.cfg, &ref_hits, &got_hits);
  EXPECT_LE(d.differ, tol.max_errors) << d.first << " (" << d.grazing << " grazing)";
  EXPECT_LE(d.grazing, rays.size() / 5) << "grazing disagreements should be rare";
}

TEST_P(AcceleratorSuite, EmptyBatchGivesEmptyResult) {
  const auto& p = GetParam();
  const Scene scene = testing::scene_from_triangles(p.mesh.triangles);
  HitBatch hits;
  std::vector<uint8_t> occ;
  auto accel = make_accelerator(p.accel, scene);
  accel->intersect(RayBatch{}, hits);
  accel->occluded(RayBatch{}, occ);
  EXPECT_EQ(hits.size(), 0u);
  EXPECT_EQ(occ.size(), 0u);
}

INSTANTIATE_TEST_SUITE_P(All, AcceleratorSuite, ::testing::ValuesIn(all_params()),
                         [](const auto& info) {
                           std::string n = info.param.accel + "_" + info.param.mesh.name;
                           for (char& c : n) if (!isalnum(static_cast<unsigned char>(c))) c = '_';
                           return n;
                         });

// Watertightness (Woop et al. 2013): rays from inside a closed mesh never escape,
// whichever shared edge or vertex they pass through.
TEST(Watertight, RaysFromInsideAClosedSphereAllHit) {
  const Scene scene = testing::scene_from_triangles(testing::sphere({0.5f, 0.5f, 0.5f}, 0.4f, 4));
  RayBatch rays = testing::random_rays(50000, 3);
  for (size_t i = 0; i < rays.size(); ++i) { rays.ox[i] = rays.oy[i] = rays.oz[i] = 0.5f; }
  for (const auto& a : accelerators()) {
    HitBatch hits;
    make_accelerator(a.name, scene)->intersect(rays, hits);
    size_t misses = 0;
    for (uint32_t prim : hits.prim) misses += prim == kInvalidId;
    EXPECT_EQ(misses, 0u) << a.name;
  }
}

}  // namespace
}  // namespace rayscout
