// Surface points of hits: hit refinement, geometric frame and ray offsets.
#pragma once

#include <cstdint>
#include <optional>

#include "rayscout/core/bounds3.h"
#include "rayscout/core/ray.h"
#include "rayscout/scene/scene.h"

namespace rayscout {

/// A shading point: where a ray hit, with the unit geometric normal turned towards the ray's
/// origin (surfaces are two-sided for reflection).
struct SurfacePoint {
  Vec3 p;            ///< (1-u-v) v0 + u v1 + v v2
  Vec3 n;            ///< unit normal on the side the ray came from
  Vec3 n_geometric;  ///< unit (v1 - v0) x (v2 - v0), not flipped (emission side)
  uint32_t prim = kInvalidId;
};

/// Hit refinement: recomputes t, u, v of a hit from its triangle with core's
/// intersect_triangle, so that accelerators whose kernels round differently (Embree) give
/// bit-identical shading. Keeps the hit as it is when the refined test misses (grazing).
Hit refine_hit(const Scene& scene, const Ray& ray, const Hit& hit);

/// The surface point of a (refined) hit.
SurfacePoint surface_point(const Scene& scene, const Ray& ray, const Hit& hit);

/// The offset of rays leaving a surface: 1e-5 times the larger of the scene's diagonal and its
/// largest absolute coordinate. Hit points carry a rounding error of a few ulps of the
/// coordinates (~1e-7 relative), so this leaves a margin of ~100x, while contact shadows stay
/// closed at the scale of 1e-5 of the scene's size and distance from the origin. See spawn_ray.
float scene_ray_epsilon(const Bounds3& bounds);

/// A ray leaving the surface point sp in unit direction w up to tmax: its origin is pushed
/// `offset` off the surface along the geometric normal, to the side w leaves on, and tmin is 0
/// (pbrt's spawned rays). The surface itself lies behind the origin; a wall nearer than the
/// offset, as at a corner, is still hit. A tmin of `offset` instead would skip that wall too and
/// let light leak through corners (11 % of the pixels of a mirror box 1000 units from the
/// origin, where the offset is 0.5 % of the box).
Ray spawn_ray(const SurfacePoint& sp, const Vec3& w, float offset, float tmax = kInfinity);

/// A shadow ray from a surface point towards a point (a light).
struct ShadowRay {
  Ray ray;    ///< spawned as spawn_ray does, ending `offset` before the target (its own surface)
  Vec3 wi;    ///< unit direction from sp.p to the target, for shading
  float dist; ///< distance from sp.p to the target
};

/// The shadow ray from sp to target; nothing when target lies within 2 offsets of sp.p
/// (there is nothing to test).
std::optional<ShadowRay> shadow_ray_to(const SurfacePoint& sp, const Vec3& target, float offset);

/// The length of ambient-occlusion rays: `configured` when positive, else 10 % of the scene
/// diagonal (1 for an empty scene).
float ao_radius_for(float configured, const Bounds3& bounds);

/// Mirror reflection of direction d about unit normal n.
inline Vec3 reflect(const Vec3& d, const Vec3& n) { return d - n * (2.0f * dot(d, n)); }

}  // namespace rayscout
