// Shadow rays of next-event estimation to point lights and area lights, shared by integrators.
#pragma once

#include <cmath>

#include "rayscout/render/bsdf.h"
#include "rayscout/render/wavefront.h"

namespace rayscout::detail {

/// One shadow ray per point light: contribution throughput f I cos / d^2.
inline void add_point_light_rays(const ShadeContext& ctx, const PathState& state, const Material& m,
                                 const SurfacePoint& sp, const Vec3& wo, ShadeOutput& out) {
  for (const PointLight& light : ctx.scene->point_lights) {
    Ray ray;
    float dist;
    if (!shadow_ray_to(sp.p, light.position, ctx.epsilon, ray, dist)) continue;
    const Vec3& wi = ray.dir;
    const float cos_s = dot(sp.n, wi);
    if (!(cos_s > 0)) continue;
    const Vec3 c = state.throughput * eval_bsdf(m, sp.n, wo, wi) * light.intensity * (cos_s / (dist * dist));
    if (max_component(c) > 0) out.add_occlusion_ray(ray, state.pixel, c);
  }
}

/// light_samples shadow rays to points on the area lights (area-measure estimator:
/// f Le cos_s cos_l / (d^2 pdf_area), averaged over the samples).
inline void add_area_light_rays(const ShadeContext& ctx, const PathState& state, const Material& m,
                                const SurfacePoint& sp, const Vec3& wo, ShadeOutput& out) {
  if (ctx.lights->empty()) return;
  const PathSampler sampler = ctx.sampler(state);
  const int n = ctx.config->light_samples;
  for (int k = 0; k < n; ++k) {
    const uint32_t dim = kDimLights + 3 * uint32_t(k);
    const LightSample ls = ctx.lights->sample(sampler.bits(dim), sampler.get(dim + 1), sampler.get(dim + 2));
    Ray ray;
    float dist;
    if (!shadow_ray_to(sp.p, ls.p, ctx.epsilon, ray, dist)) continue;
    const Vec3& wi = ray.dir;
    const float cos_s = dot(sp.n, wi), cos_l = -dot(ls.n, wi);
    if (!(cos_s > 0 && cos_l > 0)) continue;
    const Vec3 c = state.throughput * eval_bsdf(m, sp.n, wo, wi) * ls.emission *
                   (cos_s * cos_l / (dist * dist * ls.pdf_area * float(n)));
    if (max_component(c) > 0) out.add_occlusion_ray(ray, state.pixel, c);
  }
}

/// Emitted radiance towards the ray's origin (one-sided, see LightSampler).
inline Vec3 emitted(const Material& m, const SurfacePoint& sp, const Ray& ray) {
  return dot(sp.n_geometric, ray.dir) < 0 ? m.emission : Vec3{0.0f};
}

/// Adds the emission seen at a hit reached from the camera or a mirror (state.specular); after
/// diffuse bounces emitters count through next-event estimation instead, never twice.
inline void add_specular_emission(const PathState& state, const Material& m, const SurfacePoint& sp,
                                  const Ray& ray, ShadeOutput& out) {
  if (!m.emissive() || !state.specular) return;
  const Vec3 le = emitted(m, sp, ray);
  if (max_component(le) > 0) out.add_radiance(state.pixel, state.throughput * le);
}

}  // namespace rayscout::detail
