// Surface points of hits: hit refinement, geometric frame and ray offsets.
#pragma once

#include <cstdint>

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

/// The tmin of secondary rays: 1e-5 times the larger of the scene's diagonal and its largest
/// absolute coordinate. Hit points carry a rounding error of a few ulps of the coordinates
/// (~1e-7 relative), so this leaves a margin of ~100x, enough for rays leaving at more than
/// ~1 degree from the surface, while contact shadows stay closed at the scale of 1e-5 scene
/// sizes. Secondary rays start at the surface point with tmin = epsilon; shadow rays stop at
/// the light distance minus epsilon.
float scene_ray_epsilon(const Bounds3& bounds);

/// The shadow ray from a surface point p to target at distance dist: direction
/// (target - p) / dist, interval [eps, dist - eps] (the surface at p and a light's own surface
/// at target excluded). False, and ray untouched, when target lies within 2 eps of p: there
/// is nothing to test.
bool shadow_ray_to(const Vec3& p, const Vec3& target, float eps, Ray& ray, float& dist);

/// The length of ambient-occlusion rays: `configured` when positive, else 10 % of the scene
/// diagonal (1 for an empty scene).
float ao_radius_for(float configured, const Bounds3& bounds);

/// Mirror reflection of direction d about unit normal n.
inline Vec3 reflect(const Vec3& d, const Vec3& n) { return d - n * (2.0f * dot(d, n)); }

}  // namespace rayscout
