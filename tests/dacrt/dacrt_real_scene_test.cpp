// Every switch combination on a real scene's primary and shadow rays (Sibenik, when present).
#include <gtest/gtest.h>

#include "dacrt_rays.h"
#include "rayscout/accelerators.h"
#include "rayscout/core/hit_compare.h"
#include "rayscout/core/scenes_dir.h"
#include "rayscout/scene/load_scene.h"

namespace rayscout {
namespace {

TEST(DacrtRealScene, SibenikPrimaryAndShadowRaysMatchBvh) {
  const auto path = find_scene_file("sibenik/sibenik.obj");
  if (!path) GTEST_SKIP() << "sibenik/sibenik.obj not found under " << scenes_dir() << " (set RAYSCOUT_SCENES)";
  const Scene scene = load_scene(*path);
  const int n = testing::small_scale() ? 48 : 128;
  const RayBatch primary = testing::pinhole_rays({-17.0f, -10.0f, 0.0f}, {0.0f, -9.0f, 0.0f}, 70.0f, n, n);
  // The reference: the bvh accelerator, itself checked against brute force by the shared suite.
  auto ref_accel = make_accelerator("bvh", scene);
  HitBatch ref;
  ref_accel->intersect(primary, ref);
  const RayBatch shadow = testing::shadow_rays(primary, ref, scene.triangles, {0.0f, 0.0f, 0.0f});
  std::vector<uint8_t> ref_occ;
  ref_accel->occluded(shadow, ref_occ);
  size_t blocked = 0;
  for (uint8_t o : ref_occ) blocked += o;
  ASSERT_GT(shadow.size(), primary.size() / 2);
  ASSERT_GT(blocked, 0u);
  ASSERT_LT(blocked, shadow.size());
  auto combos = testing::switch_combinations();
  if (testing::small_scale()) combos.resize(8);
  for (const auto& combo : combos) {
    auto accel = make_accelerator("dacrt-rs", scene, testing::options_of(combo));
    HitBatch got;
    accel->intersect(primary, got);
    const HitDiff d = compare_hits(ref, got, 0.0f);
    EXPECT_TRUE(d.ok()) << testing::label_of(combo) << ": " << d.first;
    std::vector<uint8_t> occ;
    accel->occluded(shadow, occ);
    size_t differ = 0;
    for (size_t i = 0; i < occ.size(); ++i) differ += occ[i] != ref_occ[i];
    EXPECT_EQ(differ, 0u) << testing::label_of(combo);
  }
}

}  // namespace
}  // namespace rayscout
