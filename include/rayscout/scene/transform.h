// Transform: an affine 3D transform (a 4x4 matrix whose last row is 0 0 0 1).
#pragma once

#include "rayscout/core/vec3.h"

namespace rayscout {

/// Affine transform p' = M p, kept in double so composed transforms round once.
struct Transform {
  double m[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};  ///< rows of [A | t]; default identity

  /// p + t.
  static Transform translate(const Vec3& t);
  /// Per-axis scale (s.x, s.y, s.z) about the origin.
  static Transform scale(const Vec3& s);
  /// Rotation by deg degrees about axis (need not be unit length), right-handed.
  static Transform rotate(const Vec3& axis, double deg);

  /// This transform applied after `inner`: (*this * inner)(p) = this(inner(p)).
  Transform operator*(const Transform& inner) const;
  /// M p + t, computed in double and rounded to float once.
  Vec3 apply_point(const Vec3& p) const;
  /// True when exactly the identity (then points are copied bit for bit).
  bool is_identity() const;
  /// Determinant of the linear part: negative for a mirroring transform, which reverses
  /// every triangle's winding (and so its normal).
  double determinant() const;
};

}  // namespace rayscout
