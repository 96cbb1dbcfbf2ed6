// Accelerator: the one batch interface every ray tracer of rayscout implements.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "rayscout/core/ray.h"
#include "rayscout/core/trace_stats.h"
#include "rayscout/core/triangle.h"

namespace rayscout {

/// What building an accelerator cost.
struct BuildInfo {
  double build_ms = 0.0;      ///< wall-clock build time; 0 for methods without a build (DACRT)
  size_t memory_bytes = 0;    ///< memory of the structure, triangles excluded
};

/// A ray tracer over a fixed triangle set. Built once, then traces batches of rays; the
/// batch is the unit of work so that divide-and-conquer tracers see whole ray sets.
/// The contract every implementation keeps:
/// - A ray hits triangle p at t when intersect_triangle() (watertight, no culling) accepts it
///   with tmin <= t <= tmax, both ends included; t is in units of the unnormalised direction
///   and tmin may be negative. Accelerators other than Embree return brute force's hits bit
///   for bit (exceptions: grazing rays, docs/bvh.md); Embree's own arithmetic agrees within
///   compare-hits' tolerance.
/// - Results do not depend on the thread count (oneTBB inside each call; limit it with
///   tbb::global_control). intersect() and occluded() may run concurrently on one accelerator.
/// - stats, when non-null, are added to (never reset): rays by the batch size, the work
///   counts exactly (see counts_work()). Work counts may depend on the thread count (DACRT's
///   parallel mode) and, for occluded(), stop at each ray's first blocker found.
/// - Irregular values: a direction whose largest component lies outside [2^-32, 2^32], or
///   has a subnormal component (below FLT_MIN, not zero) and its largest below 1, is traced
///   scaled by a power of two (exact, the largest into [1, 2)) with tmin and tmax scaled
///   inversely, and t is scaled back (it may then overflow to inf, or underflow, on a real
///   hit); components and coordinates still subnormal are traced as zero, as
///   Embree reads them (a subnormal has no finite reciprocal and too few bits for the
///   watertight test). A zero direction misses, and so does a ray with an infinite or NaN
///   direction component or origin coordinate.
class Accelerator {
 public:
  virtual ~Accelerator() = default;

  /// Registry name, e.g. "bvh", "dacrt-rs".
  virtual std::string name() const = 0;
  /// Closest hit of every ray; an exact tie goes to the smaller triangle id (is_closer).
  /// hits is reset to rays.size() entries; a miss is t = inf, prim = kInvalidId, u = v = 0.
  void intersect(const RayBatch& rays, HitBatch& hits, TraceStats* stats = nullptr) const;
  /// Whether any triangle blocks each ray: occluded is reset to rays.size() bytes, 1 where
  /// intersect() would find a hit, else 0. Stops at the first blocker found.
  void occluded(const RayBatch& rays, std::vector<uint8_t>& occluded, TraceStats* stats = nullptr) const;
  /// Build time and memory.
  virtual BuildInfo build_info() const = 0;
  /// Peak scratch memory of the last trace call (DACRT's index arrays); 0 when none.
  virtual size_t last_trace_memory_bytes() const { return 0; }
  /// Whether stats receive work counts (steps, box and triangle tests); false for a peer
  /// library that does not expose them (Embree), whose stats count rays only.
  virtual bool counts_work() const { return true; }

 protected:
  /// What intersect() and occluded() run, on rays whose direction components and origin
  /// coordinates are finite and not subnormal, with the largest direction component in
  /// [2^-32, 2^32] or zero (or whose direction is NaN, to miss).
  virtual void intersect_batch(const RayBatch& rays, HitBatch& hits, TraceStats* stats) const = 0;
  virtual void occluded_batch(const RayBatch& rays, std::vector<uint8_t>& occluded, TraceStats* stats) const = 0;

  /// intersect() and occluded() with `trace` in place of the *_batch call: for a subclass's
  /// public variant of them (ShaftsAccelerator's use_lists), which must handle irregular
  /// values as the contract says.
  static void intersect_with(const RayBatch& rays, HitBatch& hits,
                             const std::function<void(const RayBatch&, HitBatch&)>& trace);
  static void occluded_with(const RayBatch& rays, std::vector<uint8_t>& occluded,
                            const std::function<void(const RayBatch&, std::vector<uint8_t>&)>& trace);
};

/// The reference: tests every ray against every triangle. Single source of truth in tests.
class BruteForce final : public Accelerator {
 public:
  /// Keeps a view of triangles: they must outlive the accelerator.
  explicit BruteForce(std::span<const Triangle> triangles) : triangles_(triangles) {}
  std::string name() const override { return "brute"; }
  BuildInfo build_info() const override { return {}; }

 private:
  void intersect_batch(const RayBatch& rays, HitBatch& hits, TraceStats* stats) const override;
  void occluded_batch(const RayBatch& rays, std::vector<uint8_t>& occluded, TraceStats* stats) const override;
  std::span<const Triangle> triangles_;
};

}  // namespace rayscout
