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

TEST_P(AcceleratorSuite, ClosestHitsMatchBruteForce) {
  const auto& p = GetParam();
  const Scene scene = testing::scene_from_triangles(p.mesh.triangles);
  const RayBatch rays = testing::nasty_rays(scene.triangles, 7);
  HitBatch ref, got;
  BruteForce(scene.triangles).intersect(rays, ref);
  make_accelerator(p.accel, scene)->intersect(rays, got);
  const HitDiff d = compare_hits(ref, got, 0.0f);  // same kernel everywhere: bit-identical t
  EXPECT_TRUE(d.ok()) << d.hit_miss << " hit/miss, " << d.other_prim << " other triangle, "
                      << d.t_mismatch << " distance; first: " << d.first;
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
  size_t differ = 0, first = 0;
  for (size_t i = 0; i < ref.size(); ++i)
    if (ref[i] != got[i] && differ++ == 0) first = i;
  EXPECT_EQ(differ, 0u) << "first differing ray " << first;
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
