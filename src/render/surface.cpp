// Hit refinement, surface points and ray offsets.
#include "rayscout/render/surface.h"

#include <cmath>
#include <limits>

#include "rayscout/core/triangle.h"

namespace rayscout {

Hit refine_hit(const Scene& scene, const Ray& ray, const Hit& hit) {
  if (!hit.hit()) return hit;
  const RayPrecomp rp(ray.dir);
  float t, u, v;
  // Unbounded interval: only the triangle decides, never the accelerator's rounding of t.
  if (intersect_triangle(ray.org, rp, scene.triangles[hit.prim], -kInfinity, kInfinity, t, u, v))
    return {t, hit.prim, u, v};
  return hit;
}

SurfacePoint surface_point(const Scene& scene, const Ray& ray, const Hit& hit) {
  const Triangle& tri = scene.triangles[hit.prim];
  SurfacePoint sp;
  sp.prim = hit.prim;
  sp.p = tri.v0 * (1.0f - hit.u - hit.v) + tri.v1 * hit.u + tri.v2 * hit.v;
  const Vec3 n = tri.normal();
  const float len = length(n);
  // A sliver so thin that its normal underflows: face the ray, never produce NaN.
  sp.n_geometric = len > 0 && std::isfinite(len) ? n / len : -normalize(ray.dir);
  sp.n = dot(sp.n_geometric, ray.dir) > 0 ? -sp.n_geometric : sp.n_geometric;
  return sp;
}

float scene_ray_epsilon(const Bounds3& bounds) {
  if (bounds.empty()) return 1e-5f;
  const float extent = std::max(length(bounds.diagonal()), max_component(max(abs(bounds.lo), abs(bounds.hi))));
  // Relative to the scene at every scale (a floor of 1e-8 once made a 3e-8 scene's offsets a
  // third of it); FLT_MIN keeps a point-sized scene's epsilon positive.
  return std::max(1e-5f * extent, std::numeric_limits<float>::min());
}

namespace {

Vec3 offset_origin(const SurfacePoint& sp, const Vec3& w, float offset) {
  const Vec3& n = sp.n_geometric;
  return sp.p + n * (dot(n, w) >= 0.0f ? offset : -offset);
}

}  // namespace

Ray spawn_ray(const SurfacePoint& sp, const Vec3& w, float offset, float tmax) {
  return {offset_origin(sp, w, offset), 0.0f, w, tmax};
}

std::optional<ShadowRay> shadow_ray_to(const SurfacePoint& sp, const Vec3& target, float offset) {
  const Vec3 d = target - sp.p;
  const float dist = length(d);
  if (!(dist > 2.0f * offset)) return std::nullopt;
  const Vec3 wi = d / dist;
  const Vec3 o = offset_origin(sp, wi, offset);
  const Vec3 to_target = target - o;
  const float len = length(to_target);
  return ShadowRay{{o, 0.0f, to_target / len, len - offset}, wi, dist};
}

float ao_radius_for(float configured, const Bounds3& bounds) {
  if (configured > 0) return configured;
  return bounds.empty() ? 1.0f : 0.1f * length(bounds.diagonal());
}

}  // namespace rayscout
