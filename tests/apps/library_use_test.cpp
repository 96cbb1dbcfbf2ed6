// README's "Using the library" example, built as an engine would build it: it must keep compiling
// and tracing through the public headers and the rayscout::accelerators target alone.
#include <gtest/gtest.h>

#include "rayscout/accelerators.h"
#include "rayscout/scene/load_scene.h"

TEST(LibraryUse, ReadmeExampleTracesTheCameraRay) {
  const rayscout::Scene scene = rayscout::resolve_scene("cornell");
  const auto accel = rayscout::make_accelerator("bvh", scene);
  rayscout::RayBatch rays;
  rays.push_back({scene.camera.eye, 0.0f, scene.camera.look_at - scene.camera.eye, rayscout::kInfinity});
  rayscout::HitBatch hits;
  accel->intersect(rays, hits);
  // The built-in Cornell box (docs/scene-format.md): the ray from the eye (0, 1, 3.4) to the
  // centre of the back wall meets the tall box (ids 20-29) first.
  ASSERT_EQ(hits.size(), 1u);
  EXPECT_GE(hits.prim[0], 20u);
  EXPECT_LE(hits.prim[0], 29u);
  rayscout::HitBatch reference;
  rayscout::BruteForce(scene.triangles).intersect(rays, reference);
  EXPECT_EQ(hits.prim[0], reference.prim[0]);
  EXPECT_EQ(hits.t[0], reference.t[0]);
}
