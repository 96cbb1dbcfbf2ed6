// default_scene: the built-in Cornell-box-like scene, and the framing camera and light.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "rayscout/scene/load_scene.h"
#include "rayscout/scene/shapes.h"
#include "scene_builder.h"

namespace rayscout {
namespace {

// Half the diagonal, without a floor, so that scenes of every scale are framed alike (a floor of
// 1e-6 put the camera of a 1e-8 scene a hundred widths away); 1 for a point-sized scene.
float framing_radius(const Bounds3& b) {
  const float r = 0.5f * length(b.diagonal());
  return r > 0.0f && std::isfinite(r) ? r : 1.0f;
}

}  // namespace

Camera framing_camera(const Bounds3& b, float fov_deg) {
  Camera c;
  c.fov_deg = fov_deg;
  const Vec3 center = b.center();
  const float radius = framing_radius(b);
  const float half_fov = 0.5f * c.fov_deg * std::numbers::pi_v<float> / 180.0f;
  const float distance = radius / std::sin(half_fov);
  c.look_at = center;
  c.eye = center + Vec3(0, 0, distance);
  c.up = Vec3(0, 1, 0);
  c.focus_distance = distance;
  return c;
}

PointLight framing_light(const Bounds3& b, const Camera& camera) {
  const float radius = framing_radius(b);
  PointLight l;
  const CameraFrame frame = camera_frame(camera, 1.0f);  // up and back of any length
  l.position = camera.eye + (frame.up - frame.forward) * (0.25f * radius);
  const Vec3 d = l.position - b.center();
  l.intensity = Vec3(dot(d, d));
  return l;
}

Scene default_scene() {
  Scene scene;
  detail::SceneBuilder builder(scene);
  auto diffuse = [](const char* name, Vec3 albedo) {
    Material m;
    m.name = name;
    m.diffuse = albedo;
    return m;
  };
  const uint32_t white = builder.define(diffuse("white", {0.725f, 0.71f, 0.68f}));
  const uint32_t red = builder.define(diffuse("red", {0.63f, 0.065f, 0.05f}));
  const uint32_t green = builder.define(diffuse("green", {0.14f, 0.45f, 0.091f}));
  Material light = diffuse("light", {0.78f, 0.78f, 0.78f});
  light.emission = Vec3(17.0f, 12.0f, 4.0f);
  const uint32_t lamp = builder.define(light);

  const Transform id;
  auto quad = [&](Vec3 c, Vec3 e1, Vec3 e2, uint32_t mat, const char* what) {
    builder.add(make_quad(c, e1, e2), id, {mat}, what);
  };
  // Walls face into the box; the +z side is open.
  quad({-1, 0, 1}, {2, 0, 0}, {0, 0, -2}, white, "floor");
  quad({-1, 2, -1}, {2, 0, 0}, {0, 0, 2}, white, "ceiling");
  quad({-1, 0, -1}, {2, 0, 0}, {0, 2, 0}, white, "back wall");
  quad({-1, 0, 1}, {0, 0, -2}, {0, 2, 0}, red, "left wall");
  quad({1, 0, -1}, {0, 0, 2}, {0, 2, 0}, green, "right wall");
  // Boxes stand on the floor, without bottom faces, turned about y as in the Cornell box.
  auto box = [&](Vec3 center, Vec3 size, float deg, const char* what) {
    const Transform xf = Transform::translate(center) * Transform::rotate({0, 1, 0}, deg);
    builder.add(make_box(size * -0.5f + Vec3(0, 0.5f * size.y, 0), size * 0.5f + Vec3(0, 0.5f * size.y, 0), false),
                xf, {white}, what);
  };
  box({0.33f, 0.0f, 0.3f}, {0.6f, 0.6f, 0.6f}, -17.0f, "short box");
  box({-0.33f, 0.0f, -0.3f}, {0.6f, 1.2f, 0.6f}, 17.0f, "tall box");
  // Area light: a 0.5 x 0.5 quad just under the ceiling, facing down.
  quad({-0.25f, 1.98f, -0.25f}, {0.5f, 0, 0}, {0, 0, 0.5f}, lamp, "ceiling light");
  builder.finish("default scene");

  // Point light just below the area light with its on-axis intensity, L * area (W/sr).
  scene.point_lights.push_back({{0.0f, 1.9f, 0.0f}, light.emission * 0.25f});
  scene.camera.eye = {0.0f, 1.0f, 3.4f};
  scene.camera.look_at = {0.0f, 1.0f, 0.0f};
  scene.camera.up = {0.0f, 1.0f, 0.0f};
  scene.camera.fov_deg = 40.0f;
  scene.camera.focus_distance = 3.4f;
  return scene;
}

}  // namespace rayscout
