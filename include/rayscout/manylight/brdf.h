// Material evaluation for many-light shading: Lambert plus normalised Phong, two-sided.
#pragma once

#include <cmath>

#include "rayscout/core/vec3.h"
#include "rayscout/scene/scene.h"

namespace rayscout {

inline constexpr float kPi = 3.14159265358979323846f;

/// Mirror direction of w (pointing away from the surface) about unit normal n.
inline Vec3 reflect(const Vec3& w, const Vec3& n) { return 2.0f * dot(w, n) * n - w; }

/// BRDF f_r(wi, wo) in sr^-1 for unit directions pointing away from the surface and the unit
/// normal n on their side. Diffuse: Kd / pi. Glossy: Kd / pi + Ks (e + 2) / (2 pi) cos^e(alpha)
/// with alpha between reflect(wi) and wo (energy-normalised Phong). Mirror: 0 (a delta lobe
/// never meets a point light).
inline Vec3 eval_brdf(const Material& m, const Vec3& n, const Vec3& wi, const Vec3& wo) {
  if (m.type == Material::Type::Mirror) return Vec3(0.0f);
  Vec3 f = m.diffuse * (1.0f / kPi);
  if (m.type == Material::Type::Glossy) {
    const float c = dot(reflect(wi, n), wo);
    if (c > 0.0f) f += m.specular * ((m.exponent + 2.0f) / (2.0f * kPi) * std::pow(c, m.exponent));
  }
  return f;
}

/// Mean of the colour channels: the scalar that probabilities and variances use.
inline float luminance(const Vec3& c) { return (c.x + c.y + c.z) * (1.0f / 3.0f); }

}  // namespace rayscout
