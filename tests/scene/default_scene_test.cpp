// The built-in Cornell-box-like scene.
#include <gtest/gtest.h>

#include "rayscout/scene/load_scene.h"

namespace rayscout {
namespace {

TEST(DefaultScene, LayoutMaterialsAndLights) {
  const Scene s = default_scene();
  ASSERT_EQ(s.triangles.size(), 32u);  // 5 walls + 2 boxes of 5 faces + light, 2 triangles each
  ASSERT_EQ(s.material_ids.size(), s.triangles.size());
  const Bounds3 b = s.bounds();
  EXPECT_EQ(b.lo.x, -1.0f); EXPECT_EQ(b.lo.y, 0.0f); EXPECT_EQ(b.lo.z, -1.0f);
  EXPECT_EQ(b.hi.x, 1.0f); EXPECT_EQ(b.hi.y, 2.0f); EXPECT_EQ(b.hi.z, 1.0f);
  for (const auto& t : s.triangles) EXPECT_GT(t.area(), 0.0f);
  EXPECT_EQ(s.material_of(6).name, "red");
  EXPECT_EQ(s.material_of(8).name, "green");
  // The area light is the last quad, facing down, just under the ceiling.
  EXPECT_EQ(s.emissive_triangles, (std::vector<uint32_t>{30, 31}));
  EXPECT_LT(s.triangles[30].normal().y, 0.0f);
  EXPECT_FLOAT_EQ(s.triangles[30].area() + s.triangles[31].area(), 0.25f);
  ASSERT_EQ(s.point_lights.size(), 1u);
  EXPECT_GT(s.point_lights[0].position.y, 1.8f);
  EXPECT_LT(s.point_lights[0].position.y, 1.98f);
  // Every wall faces into the box: its normal points towards the centre.
  const Vec3 c(0, 1, 0);
  for (uint32_t t = 0; t < 10; ++t) EXPECT_GT(dot(s.triangles[t].normal(), c - s.triangles[t].centroid()), 0.0f);
  // Camera outside the open +z side, looking in.
  EXPECT_GT(s.camera.eye.z, 1.0f);
  EXPECT_LT(s.camera.look_at.z, s.camera.eye.z);
  EXPECT_TRUE(s.warnings.empty());
}

TEST(DefaultScene, ResolveScene) {
  EXPECT_EQ(resolve_scene("").triangles.size(), 32u);
  EXPECT_EQ(resolve_scene("cornell").triangles.size(), 32u);
  EXPECT_THROW(resolve_scene("/nonexistent/x.obj"), InputError);
}

}  // namespace
}  // namespace rayscout
