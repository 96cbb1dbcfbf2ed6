// Next-event estimation (shadow rays to point and area lights), the emission seen at hits, and
// the MIS weights that join the two: shared by the direct, area and path integrators.
#pragma once

#include <cmath>

#include "rayscout/render/bsdf.h"
#include "wavefront.h"

namespace rayscout::detail {

/// One shadow ray per point light: contribution throughput f I cos / d^2.
inline void add_point_light_rays(const ShadeContext& ctx, const PathState& state, const Material& m,
                                 const SurfacePoint& sp, const Vec3& wo, ShadeOutput& out) {
  for (const PointLight& light : ctx.scene->point_lights) {
    const auto shadow = shadow_ray_to(sp, light.position, ctx.epsilon);
    if (!shadow) continue;
    const auto& [ray, wi, dist] = *shadow;
    const float cos_s = dot(sp.n, wi);
    if (!(cos_s > 0)) continue;
    const Vec3 c = state.throughput * eval_bsdf(m, sp.n, wo, wi) * light.intensity * (cos_s / (dist * dist));
    if (max_component(c) > 0) out.add_occlusion_ray(ray, state.pixel, c);
  }
}

/// Power heuristic (Veach 1997, eq. 9.13, beta = 2): the MIS weight of a sample of a strategy
/// with nf samples at density f, against a strategy with ng samples at density g. Written as
/// a ratio so that an infinite density (a light seen edge-on) gives 1 or 0, not NaN.
inline float power_heuristic(float nf, float f, float ng, float g) {
  const float a = nf * f, b = ng * g;
  if (!(a > 0)) return 0.0f;
  if (!(b > 0)) return 1.0f;
  const float r = b / a;
  return std::isnan(r) ? 0.5f : 1.0f / (1.0f + r * r);
}

/// An area density at a light point turned into a solid-angle density seen from dist2 away,
/// at cosine cos_l (> 0) to the light's normal: pdf_area * d^2 / cos_l.
inline float solid_angle_pdf(float pdf_area, float dist2, float cos_l) { return pdf_area * dist2 / cos_l; }

/// Solid-angle density with which the light sampler picks the point sp of an emitter, seen
/// from `from`; 0 where it never picks it.
inline float light_pdf_solid_angle(const LightSampler& lights, const SurfacePoint& sp, const Vec3& from) {
  const float pdf_area = lights.pdf_area(sp.prim);
  if (!(pdf_area > 0)) return 0.0f;
  const Vec3 d = sp.p - from;
  const float dist2 = dot(d, d);
  const float cos_l = -dot(sp.n_geometric, d) / std::sqrt(dist2);
  return cos_l > 0 ? solid_angle_pdf(pdf_area, dist2, cos_l) : 0.0f;
}

/// light_samples shadow rays to points on the area lights (area-measure estimator:
/// f Le cos_s cos_l / (d^2 pdf_area), averaged over the samples). With `mis`, the next bounce
/// samples the BSDF too and counts the emitters it hits (add_emission); both are then weighted
/// by the power heuristic.
inline void add_area_light_rays(const ShadeContext& ctx, const PathState& state, const Material& m,
                                const SurfacePoint& sp, const Vec3& wo, ShadeOutput& out, bool mis = false) {
  if (ctx.lights->empty()) return;
  const PathSampler sampler = ctx.sampler(state);
  const int n = ctx.config->light_samples;
  for (int k = 0; k < n; ++k) {
    const LightSample ls = sample_light(*ctx.lights, sampler, k);
    const auto shadow = shadow_ray_to(sp, ls.p, ctx.epsilon);
    if (!shadow) continue;
    const auto& [ray, wi, dist] = *shadow;
    const float cos_s = dot(sp.n, wi), cos_l = -dot(ls.n, wi);
    if (!(cos_s > 0 && cos_l > 0)) continue;
    float weight = 1.0f;
    if (mis) weight = power_heuristic(float(n), solid_angle_pdf(ls.pdf_area, dist * dist, cos_l), 1.0f,
                                      pdf_bsdf(m, sp.n, wo, wi));
    const Vec3 c = state.throughput * eval_bsdf(m, sp.n, wo, wi) * ls.emission *
                   (weight * cos_s * cos_l / (dist * dist * ls.pdf_area * float(n)));
    if (max_component(c) > 0) out.add_occlusion_ray(ray, state.pixel, c);
  }
}

/// Emitted radiance towards the ray's origin (one-sided, see LightSampler).
inline Vec3 emitted(const Material& m, const SurfacePoint& sp, const Ray& ray) {
  return dot(sp.n_geometric, ray.dir) < 0 ? m.emission : Vec3{0.0f};
}

/// Adds the emission seen at a hit: in full when reached from the camera or a mirror
/// (state.specular); after another bounce only when that bounce shares the emitters with
/// next-event estimation (state.bsdf_pdf > 0), with the BSDF strategy's MIS weight. Otherwise
/// next-event estimation alone counts them, so nothing is counted twice.
inline void add_emission(const ShadeContext& ctx, const PathState& state, const Material& m, const SurfacePoint& sp,
                         const Ray& ray, ShadeOutput& out) {
  if (!m.emissive() || !(state.specular || state.bsdf_pdf > 0)) return;
  const Vec3 le = emitted(m, sp, ray);
  if (!(max_component(le) > 0)) return;
  float weight = 1.0f;
  if (!state.specular)
    weight = power_heuristic(1.0f, state.bsdf_pdf, float(ctx.config->light_samples),
                             light_pdf_solid_angle(*ctx.lights, sp, ray.org));
  out.add_radiance(state.pixel, state.throughput * le * weight);
}

}  // namespace rayscout::detail
