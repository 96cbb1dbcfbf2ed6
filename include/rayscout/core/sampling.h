// Warping [0,1)^2 to directions and to points on triangles: the one copy every module samples with.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include "rayscout/core/vec3.h"

namespace rayscout {

/// Orthonormal basis (t, b, n) around unit n (Duff et al., JCGT 2017).
inline void orthonormal_basis(const Vec3& n, Vec3& t, Vec3& b) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float c = n.x * n.y * a;
  t = {1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x};
  b = {c, sign + n.y * n.y * a, -n.y};
}

/// Cosine-distributed unit direction around unit n from [0,1)^2 (pdf cos(theta) / pi).
inline Vec3 sample_cosine_hemisphere(const Vec3& n, float u1, float u2) {
  const float r = std::sqrt(u1), phi = 2.0f * std::numbers::pi_v<float> * u2;
  const float x = r * std::cos(phi), y = r * std::sin(phi);
  const float z = std::sqrt(std::max(0.0f, 1.0f - u1));
  Vec3 t, b;
  orthonormal_basis(n, t, b);
  return normalize(t * x + b * y + n * z);
}

/// Barycentrics (b1, b2) of a uniform point on a triangle from [0,1)^2: the point is
/// (1 - b1 - b2) v0 + b1 v1 + b2 v2 (the square-root map, Turk 1990 / Shirley 1992).
struct TriangleSample { float b1, b2; };
inline TriangleSample sample_triangle(float u1, float u2) {
  const float su = std::sqrt(u1);
  return {1.0f - su, u2 * su};
}

}  // namespace rayscout
