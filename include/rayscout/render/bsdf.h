// Material scattering: evaluation and sampling of the diffuse, mirror and glossy lobes. The one
// BSDF of rayscout: the integrators of the render module and the many-light renderer's VPLs and
// shading both use it.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "rayscout/core/sampling.h"
#include "rayscout/render/surface.h"
#include "rayscout/scene/scene.h"

namespace rayscout {

inline constexpr float kInvPi = std::numbers::inv_pi_v<float>;

/// Probability of sampling the glossy lobe of a Glossy material (by reflectance).
inline float glossy_lobe_probability(const Material& m) {
  const float d = max_component(m.diffuse), s = max_component(m.specular);
  return d + s > 0 ? s / (d + s) : 0.0f;
}

/// cos^e of the angle between wi and the mirror direction of wo (0 below it).
inline float phong_cos_power(const Material& m, const Vec3& n, const Vec3& wo, const Vec3& wi) {
  // Two unit vectors' dot product can round to 1 + ulp, and (1 + ulp)^e is inf for a large e.
  const float c = std::min(dot(reflect(-wo, n), wi), 1.0f);
  return c > 0 ? std::pow(c, m.exponent) : 0.0f;
}

/// BRDF value f(wo, wi) of the non-delta part: Lambert kd / pi, plus for Glossy the
/// normalised modified Phong lobe ks (e + 2) / (2 pi) cos^e(alpha) (Lafortune & Willems 1994).
/// wo towards the viewer, wi towards the light, n on wo's side. Mirrors give 0.
inline Vec3 eval_bsdf(const Material& m, const Vec3& n, const Vec3& wo, const Vec3& wi) {
  if (m.type == Material::Type::Mirror) return Vec3{0.0f};
  Vec3 f = m.diffuse * kInvPi;
  if (m.type == Material::Type::Glossy)
    f += m.specular * ((m.exponent + 2.0f) * 0.5f * kInvPi * phong_cos_power(m, n, wo, wi));
  return f;
}

/// Solid-angle density with which sample_bsdf returns wi (non-delta part; 0 for mirrors and
/// below the surface): cosine for Diffuse, the lobe mixture for Glossy.
inline float pdf_bsdf(const Material& m, const Vec3& n, const Vec3& wo, const Vec3& wi) {
  const float cos_n = dot(wi, n);
  if (m.type == Material::Type::Mirror || !(cos_n > 0)) return 0.0f;
  const float pdf_d = cos_n * kInvPi;  // cosine-weighted hemisphere
  if (m.type == Material::Type::Diffuse) return pdf_d;
  const float ps = glossy_lobe_probability(m);
  // The Phong lobe's density over the whole sphere, not renormalised to the hemisphere: the
  // lobe's directions below the surface are sampled too, and sample_bsdf returns them invalid
  // (a zero-valued sample), which keeps the estimator unbiased.
  const float pdf_s = (m.exponent + 1.0f) * 0.5f * kInvPi * phong_cos_power(m, n, wo, wi);
  return (1.0f - ps) * pdf_d + ps * pdf_s;
}

/// Direction around unit r at density (e + 1) / (2 pi) cos^e(alpha) from [0,1)^2 (Lafortune &
/// Willems 1994): cos(alpha) = u1^(1 / (e + 1)) inverts the CDF of cos(alpha), phi = 2 pi u2.
inline Vec3 sample_phong_lobe(const Vec3& r, float exponent, float u1, float u2) {
  const float cos_a = std::pow(u1, 1.0f / (exponent + 1.0f));
  const float sin_a = std::sqrt(std::max(0.0f, 1.0f - cos_a * cos_a));
  const float phi = 2.0f * std::numbers::pi_v<float> * u2;
  Vec3 t, b;
  orthonormal_basis(r, t, b);
  return normalize(t * (sin_a * std::cos(phi)) + b * (sin_a * std::sin(phi)) + r * cos_a);
}

/// A sampled scattering direction with weight f cos / pdf.
struct BsdfSample {
  Vec3 wi;
  Vec3 weight{0.0f};
  float pdf = 0;          ///< solid-angle density of wi (0 for a mirror bounce)
  bool specular = false;  ///< a mirror (delta) bounce
  bool valid = false;
};

/// Samples wi: mirror reflection; cosine hemisphere for Diffuse; for Glossy one lobe chosen
/// by reflectance, weighted with the one-sample mixture pdf (balance heuristic over lobes).
inline BsdfSample sample_bsdf(const Material& m, const Vec3& n, const Vec3& wo, float u0, float u1, float u2) {
  BsdfSample s;
  if (m.type == Material::Type::Mirror) {
    s.wi = reflect(-wo, n);
    s.weight = m.specular;
    s.specular = s.valid = true;
    return s;
  }
  if (m.type == Material::Type::Diffuse) {
    s.wi = sample_cosine_hemisphere(n, u1, u2);
    s.weight = m.diffuse;  // f cos / pdf = (kd / pi) cos / (cos / pi)
    s.pdf = pdf_bsdf(m, n, wo, s.wi);
    s.valid = true;
    return s;
  }
  s.wi = u0 < glossy_lobe_probability(m) ? sample_phong_lobe(reflect(-wo, n), m.exponent, u1, u2)
                                          : sample_cosine_hemisphere(n, u1, u2);
  const float pdf = pdf_bsdf(m, n, wo, s.wi);
  // A density below float's normal range only comes from the Phong lobe's rim without a
  // diffuse lobe (u1 = 0: cos(alpha) = 0, and dot(r, wi) is rounding noise whose e-th power is
  // denormal). cos / pdf would overflow there, and the direction carries no light worth
  // counting (f cos ~ pdf): the sample is dropped.
  if (!(pdf >= std::numeric_limits<float>::min())) return s;
  s.weight = eval_bsdf(m, n, wo, s.wi) * (dot(s.wi, n) / pdf);
  s.pdf = pdf;
  s.valid = true;
  return s;
}

}  // namespace rayscout
