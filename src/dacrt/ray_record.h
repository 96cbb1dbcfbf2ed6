// RayRecord: the 32-byte per-ray state every DACRT kernel reads (origin, reciprocal
// direction, tmin and the current closest-hit distance t that filtering uses).
#pragma once

#include <cstdint>
#include <limits>

#include "rayscout/core/triangle.h"

namespace rayscout::dacrt {

/// Per-ray state of one trace call; index = ray id. t shrinks as hits are found; a ray that
/// left the set (occluded) has a NaN tmin, so every box and triangle test fails (no input ray
/// has one: rays with an empty or NaN segment are left out at setup).
struct alignas(32) RayRecord {
  float ox, oy, oz, tmin;
  float ix, iy, iz, t;  ///< 1 / direction (as RayPrecomp::inv_dir), current closest t

  /// Whether the ray runs towards larger coordinates along axis (0, 1, 2): the side whose
  /// child it meets first (Afra's child order; the tie-break of the vote rules).
  bool goes_up(int axis) const { return (axis == 0 ? ix : (axis == 1 ? iy : iz)) >= 0.0f; }
};
static_assert(sizeof(RayRecord) == 32);

/// The watertight test's per-ray constants (RayPrecomp without inv_dir, which RayRecord
/// holds) in 16 bytes: shear sx, sy, sz and the axes packed as kx | ky << 8 | kz << 16.
struct alignas(16) RayShear {
  float sx, sy, sz;
  uint32_t k;
};
static_assert(sizeof(RayShear) == 16);

/// The RayPrecomp of core's intersect_triangle for a RayShear (inv_dir is not used by it).
inline RayPrecomp to_precomp(const RayShear& s) {
  RayPrecomp p;
  p.kx = int(s.k & 0xFF); p.ky = int((s.k >> 8) & 0xFF); p.kz = int(s.k >> 16);
  p.sx = s.sx; p.sy = s.sy; p.sz = s.sz;
  return p;
}

/// RayShear of core's RayPrecomp(dir) (the same operations).
inline RayShear shear_of(const RayPrecomp& p) {
  return {p.sx, p.sy, p.sz, uint32_t(p.kx) | uint32_t(p.ky) << 8 | uint32_t(p.kz) << 16};
}

/// A triangle's bounding box as two 16-byte rows (lo, hi; the 4th lanes are 0), so binning
/// extends bins with one SIMD min and max each. Its centre is center(), as Bounds3::center().
struct alignas(32) TriBox {
  float lo[4], hi[4];
  TriBox() = default;
  explicit TriBox(const Bounds3& b) : lo{b.lo.x, b.lo.y, b.lo.z, 0.0f}, hi{b.hi.x, b.hi.y, b.hi.z, 0.0f} {}
  /// Centre along one axis, exactly Bounds3::center()[axis].
  float center(int axis) const { return (lo[axis] + hi[axis]) * 0.5f; }
};
static_assert(sizeof(TriBox) == 32);

/// Marks an any-hit ray as done. Not tmin = +inf (with t = -inf), which filtering reads as a
/// segment at infinity (filter_tmin) and an input ray [+inf, +inf] has.
inline void retire(RayRecord& r) { r.tmin = std::numeric_limits<float>::quiet_NaN(); }

/// Whether retire() marked r.
inline bool retired(const RayRecord& r) { return r.tmin != r.tmin; }

}  // namespace rayscout::dacrt
