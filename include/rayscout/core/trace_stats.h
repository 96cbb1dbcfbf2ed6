// TraceStats: exact work counters of one trace call.
#pragma once

#include <cstdint>

namespace rayscout {

/// Exact work counts, added to by each trace call that is given a non-null pointer (see
/// Accelerator); the kernels are instantiated twice so the uncounted path pays nothing.
struct TraceStats {
  uint64_t rays = 0;             ///< rays traced, every ray of each batch
  uint64_t traversal_steps = 0;  ///< nodes popped / visited (DACRT: recursion calls)
  uint64_t ray_box_tests = 0;    ///< ray-box slab tests, one per ray and box
  uint64_t ray_tri_tests = 0;    ///< ray-triangle tests, one per ray and triangle

  TraceStats& operator+=(const TraceStats& o) {
    rays += o.rays; traversal_steps += o.traversal_steps;
    ray_box_tests += o.ray_box_tests; ray_tri_tests += o.ray_tri_tests;
    return *this;
  }
};

/// Throughput in millions of rays per second of `rays` traced in `ms` milliseconds (0 for no time).
inline double mrays_per_s(uint64_t rays, double ms) { return ms > 0 ? double(rays) / (ms * 1e3) : 0.0; }

}  // namespace rayscout
