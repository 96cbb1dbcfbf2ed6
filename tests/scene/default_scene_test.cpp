// The built-in Cornell-box-like scene.
#include <gtest/gtest.h>

#include <cmath>

#include "rayscout/scene/load_scene.h"
#include "temp_files.h"

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

// The values of the table in docs/scene-format.md ("The built-in scene").
TEST(DefaultScene, DocumentedValues) {
  const Scene s = default_scene();
  ASSERT_EQ(s.triangles.size(), 32u);
  const auto name_of = [&](uint32_t t) { return s.material_of(t).name; };
  for (uint32_t t = 0; t < 6; ++t) EXPECT_EQ(name_of(t), "white") << t;  // floor, ceiling, back wall
  EXPECT_EQ(name_of(6), "red");
  EXPECT_EQ(name_of(7), "red");
  EXPECT_EQ(name_of(8), "green");
  EXPECT_EQ(name_of(9), "green");
  for (uint32_t t = 10; t < 30; ++t) EXPECT_EQ(name_of(t), "white") << t;  // the boxes
  EXPECT_EQ(name_of(30), "light");
  EXPECT_EQ(name_of(31), "light");
  EXPECT_EQ(s.material_of(0).diffuse, Vec3(0.725f, 0.71f, 0.68f));
  EXPECT_EQ(s.material_of(6).diffuse, Vec3(0.63f, 0.065f, 0.05f));
  EXPECT_EQ(s.material_of(8).diffuse, Vec3(0.14f, 0.45f, 0.091f));
  EXPECT_EQ(s.material_of(30).diffuse, Vec3(0.78f));
  EXPECT_EQ(s.material_of(30).emission, Vec3(17, 12, 4));
  // Floor y = 0, ceiling y = 2, back wall z = -1, left x = -1, right x = 1, the light at y = 1.98.
  const auto box_of = [&](uint32_t first, uint32_t count) {
    Bounds3 b;
    for (uint32_t t = first; t < first + count; ++t) b.extend(s.triangles[t].bounds());
    return b;
  };
  EXPECT_EQ(box_of(0, 2).hi.y, 0.0f);
  EXPECT_EQ(box_of(2, 2).lo.y, 2.0f);
  EXPECT_EQ(box_of(4, 2).hi.z, -1.0f);
  EXPECT_EQ(box_of(6, 2).hi.x, -1.0f);
  EXPECT_EQ(box_of(8, 2).lo.x, 1.0f);
  const Bounds3 lamp = box_of(30, 2);
  EXPECT_EQ(lamp.lo, Vec3(-0.25f, 1.98f, -0.25f));
  EXPECT_EQ(lamp.hi, Vec3(0.25f, 1.98f, 0.25f));
  // The boxes: centred (in x and z) where the table says, standing on the floor, 0.6 and 1.2 high.
  const Bounds3 short_box = box_of(10, 10), tall_box = box_of(20, 10);
  EXPECT_NEAR(short_box.center().x, 0.33f, 1e-6f);
  EXPECT_NEAR(short_box.center().z, 0.3f, 1e-6f);
  EXPECT_NEAR(short_box.lo.y, 0.0f, 1e-6f);
  EXPECT_NEAR(short_box.hi.y, 0.6f, 1e-6f);
  EXPECT_NEAR(tall_box.center().x, -0.33f, 1e-6f);
  EXPECT_NEAR(tall_box.center().z, -0.3f, 1e-6f);
  EXPECT_NEAR(tall_box.hi.y, 1.2f, 1e-6f);
  // Point light: the area light's on-axis intensity, emission x area.
  ASSERT_EQ(s.point_lights.size(), 1u);
  EXPECT_EQ(s.point_lights[0].position, Vec3(0, 1.9f, 0));
  EXPECT_EQ(s.point_lights[0].intensity, Vec3(4.25f, 3, 1));
  EXPECT_EQ(s.camera.eye, Vec3(0, 1, 3.4f));
  EXPECT_EQ(s.camera.look_at, Vec3(0, 1, 0));
  EXPECT_EQ(s.camera.up, Vec3(0, 1, 0));
  EXPECT_EQ(s.camera.fov_deg, 40.0f);
  EXPECT_EQ(s.camera.lens_radius, 0.0f);
}

// A bare mesh's camera and light (docs/scene-format.md): looking down -z at the bounds' centre
// from where the bounding sphere fills a 60 degree view, so at 2 radii; the light a quarter
// radius above and behind the camera, with intensity d^2 for its distance d to the centre.
TEST(DefaultScene, BareMeshFramingCameraAndLight) {
  testing::TempDir dir;
  const Scene s = load_scene(dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
  const float r = 0.5f * std::sqrt(2.0f);  // half the bounds' diagonal
  const Vec3 centre(0.5f, 0.5f, 0);
  EXPECT_EQ(s.camera.look_at, centre);
  EXPECT_NEAR(s.camera.eye.x, 0.5f, 1e-6f);
  EXPECT_NEAR(s.camera.eye.y, 0.5f, 1e-6f);
  EXPECT_NEAR(s.camera.eye.z, 2 * r, 1e-5f);
  EXPECT_EQ(s.camera.up, Vec3(0, 1, 0));
  EXPECT_EQ(s.camera.fov_deg, 60.0f);
  EXPECT_EQ(s.camera.lens_radius, 0.0f);
  EXPECT_NEAR(s.camera.focus_distance, 2 * r, 1e-5f);
  ASSERT_EQ(s.point_lights.size(), 1u);
  const Vec3 p = s.point_lights[0].position;
  EXPECT_NEAR(p.x, 0.5f, 1e-6f);
  EXPECT_NEAR(p.y, 0.5f + 0.25f * r, 1e-5f);
  EXPECT_NEAR(p.z, 2.25f * r, 1e-5f);
  const float d2 = dot(p - centre, p - centre);
  EXPECT_NEAR(s.point_lights[0].intensity.x, d2, 1e-5f);
  EXPECT_NEAR(d2, 5.125f * r * r, 1e-5f);
  EXPECT_TRUE(s.warnings.empty());
}

TEST(DefaultScene, ResolveScene) {
  EXPECT_EQ(resolve_scene("").triangles.size(), 32u);
  EXPECT_EQ(resolve_scene("cornell").triangles.size(), 32u);
  EXPECT_THROW(resolve_scene("/nonexistent/x.obj"), InputError);
}

}  // namespace
}  // namespace rayscout
