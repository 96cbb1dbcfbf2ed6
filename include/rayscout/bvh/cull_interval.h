// CullInterval: the conservative [near, far] limits of box tests during BVH traversal.
#pragma once

#include "rayscout/core/bounds3.h"
#include "rayscout/core/ray.h"

namespace rayscout {

/// Widens the ray interval a box test is run with. A box's slab distances and a triangle's t
/// (watertight arithmetic) round differently: a triangle hit at t <= best_t can sit in a box
/// whose computed entry is a few ulps beyond best_t (coplanar duplicates), and a hit accepted
/// at t >= tmin ~ 0 (rays leaving a surface) can sit in a box whose computed exit is slightly
/// negative. Box tests therefore use [tmin - slack, t + slack], with slack = 2^-17 relative
/// plus 2^-20 of the coordinate magnitude along the ray's dominant axis (about 16 ulps of
/// every coordinate). Triangle tests keep the exact interval, so results stay identical to
/// brute force; the cost is a few extra box visits.
/// Public because it is part of the seeded traversal's contract (Bvh2/WideBvh::intersect with
/// start entries): a caller that box-tests start entries on the traversal's behalf (shafts'
/// entry boxes) must use the same interval, which Bvh2/WideBvh::cull_interval(ray) give.
struct CullInterval {
  /// Slack relative to the distance itself, 2^-17.
  static constexpr float kRelativeSlack = 0x1p-17f;
  /// Slack relative to the coordinates' magnitude, 2^-20 (divided by the dominant direction
  /// component, it becomes a distance along the ray).
  static constexpr float kCoordinateSlack = 0x1p-20f;

  float abs_slack;  ///< kCoordinateSlack of this ray's coordinates, as a distance along it

  CullInterval(const Bounds3& scene, const Ray& ray) {
    const float coords = max_component(max(abs(scene.lo), abs(scene.hi))) + max_component(abs(ray.org));
    abs_slack = coords * kCoordinateSlack / max_component(abs(ray.dir));
  }
  /// Box-test far limit for a current closest distance t (|t|: a hit behind the origin, for
  /// a ray with tmin < 0, must widen the interval too). t = -inf gives +inf, not NaN (which
  /// culled every box): every triangle whose t overflows to -inf ties there, wherever its box,
  /// and the tie goes to the smaller id, so no box is culled.
  float far(float t) const {
    return t == -kInfinity ? kInfinity : t + (t < 0 ? -t : t) * kRelativeSlack + abs_slack;
  }
  /// Box-test near limit for the ray's tmin; tmin = +inf gives -inf (the mirror of far).
  float near(float tmin) const {
    return tmin == kInfinity ? -kInfinity : tmin - (tmin < 0 ? -tmin : tmin) * kRelativeSlack - abs_slack;
  }
};

}  // namespace rayscout
