// Bounds3: an axis-aligned bounding box.
#pragma once

#include <limits>

#include "rayscout/core/vec3.h"

namespace rayscout {

/// Axis-aligned box [lo, hi]; the default box is empty (lo = +inf, hi = -inf).
struct Bounds3 {
  Vec3 lo{std::numeric_limits<float>::infinity()};
  Vec3 hi{-std::numeric_limits<float>::infinity()};

  void extend(const Vec3& p) { lo = min(lo, p); hi = max(hi, p); }
  void extend(const Bounds3& b) { lo = min(lo, b.lo); hi = max(hi, b.hi); }
  bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
  Vec3 diagonal() const { return hi - lo; }
  Vec3 center() const { return (lo + hi) * 0.5f; }
  /// Surface area; 0 for an empty box.
  float surface_area() const {
    if (empty()) return 0.0f;
    Vec3 d = diagonal();
    return 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x);
  }
  int largest_axis() const { return max_axis(diagonal()); }
  bool contains(const Bounds3& b) const {
    return lo.x <= b.lo.x && lo.y <= b.lo.y && lo.z <= b.lo.z &&
           hi.x >= b.hi.x && hi.y >= b.hi.y && hi.z >= b.hi.z;
  }
};

inline Bounds3 merge(Bounds3 a, const Bounds3& b) { a.extend(b); return a; }

}  // namespace rayscout
