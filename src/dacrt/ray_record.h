// RayRecord: the 32-byte per-ray state every DACRT kernel reads (origin, reciprocal
// direction, tmin and the current closest-hit distance t that filtering uses).
#pragma once

#include <cstdint>
#include <limits>

namespace rayscout::dacrt {

/// Per-ray state of one trace call; index = ray id. t shrinks as hits are found; a ray that
/// left the set (occluded) has t = -inf and tmin = +inf so every box and triangle test fails.
struct alignas(32) RayRecord {
  float ox, oy, oz, tmin;
  float ix, iy, iz, t;  ///< 1 / direction (as RayPrecomp::inv_dir), current closest t
};
static_assert(sizeof(RayRecord) == 32);

/// Marks an any-hit ray as done.
inline void retire(RayRecord& r) {
  r.t = -std::numeric_limits<float>::infinity();
  r.tmin = std::numeric_limits<float>::infinity();
}

}  // namespace rayscout::dacrt
