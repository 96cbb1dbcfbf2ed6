// DVec3: a three-double vector, for geometry that judges float arithmetic (hit_compare) or
// must round to float once, at the end (bench/audit/probe_rays).
#pragma once

#include <algorithm>
#include <cmath>

#include "rayscout/core/vec3.h"

namespace rayscout {

/// A 3D vector of doubles: a float Vec3 widens exactly, and a few operations on it add errors
/// ~2^29 times smaller than the same ones in float.
struct DVec3 {
  double x = 0, y = 0, z = 0;

  constexpr DVec3() = default;
  constexpr DVec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
  constexpr explicit DVec3(const Vec3& v) : x(v.x), y(v.y), z(v.z) {}

  constexpr DVec3 operator+(const DVec3& b) const { return {x + b.x, y + b.y, z + b.z}; }
  constexpr DVec3 operator-(const DVec3& b) const { return {x - b.x, y - b.y, z - b.z}; }
  constexpr DVec3 operator*(double s) const { return {x * s, y * s, z * s}; }
};

constexpr double dot(const DVec3& a, const DVec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr DVec3 cross(const DVec3& a, const DVec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(const DVec3& a) { return std::sqrt(dot(a, a)); }
inline DVec3 normalize(const DVec3& a) { return a * (1.0 / length(a)); }
/// Rounded to the nearest floats.
constexpr Vec3 to_float(const DVec3& a) { return {float(a.x), float(a.y), float(a.z)}; }
/// The largest absolute coordinate (the max norm).
inline double max_abs(const DVec3& a) { return std::max({std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)}); }

}  // namespace rayscout
