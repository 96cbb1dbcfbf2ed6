// Accelerator: the batch entry points every ray tracer shares (tiny directions, then the
// tracer's own batch loop).
#include "rayscout/core/accelerator.h"

#include <cfloat>
#include <cmath>
#include <utility>
#include <vector>

namespace rayscout {
namespace {

/// The k with 2^k times the largest component of (dx, dy, dz) in [1, 2) when every component
/// is subnormal and one is not zero; else 0. Such a direction has no finite reciprocal
/// (1 / 2.9e-39 overflows), so the slab tests and the watertight test's 1/d_kz would see inf.
int tiny_direction_exponent(float dx, float dy, float dz) {
  const float m = max_component(abs(Vec3(dx, dy, dz)));
  if (std::isnan(dx) || std::isnan(dy) || std::isnan(dz) || m == 0.0f || m >= FLT_MIN) return 0;
  return -std::ilogb(m);
}

/// Rays of the batch with tiny directions and their exponents (empty almost always: one
/// branch-free pass finds out first).
std::vector<std::pair<size_t, int>> tiny_directions(const RayBatch& rays) {
  bool any = false;
  for (size_t i = 0; i < rays.size(); ++i) {
    const float m = max_component(abs(Vec3(rays.dx[i], rays.dy[i], rays.dz[i])));
    any |= (m > 0.0f) & (m < FLT_MIN);
  }
  std::vector<std::pair<size_t, int>> tiny;
  if (!any) return tiny;
  for (size_t i = 0; i < rays.size(); ++i)
    if (const int k = tiny_direction_exponent(rays.dx[i], rays.dy[i], rays.dz[i])) tiny.emplace_back(i, k);
  return tiny;
}

/// rays with the tiny directions scaled by 2^k (exact) and tmin, tmax by 2^-k, so that the
/// same points lie at the scaled distances.
RayBatch scaled_up(const RayBatch& rays, const std::vector<std::pair<size_t, int>>& tiny) {
  RayBatch scaled = rays;
  for (const auto& [i, k] : tiny) {
    scaled.dx[i] = std::ldexp(rays.dx[i], k);
    scaled.dy[i] = std::ldexp(rays.dy[i], k);
    scaled.dz[i] = std::ldexp(rays.dz[i], k);
    scaled.tmin[i] = std::ldexp(rays.tmin[i], -k);
    scaled.tmax[i] = std::ldexp(rays.tmax[i], -k);
  }
  return scaled;
}

}  // namespace

void Accelerator::intersect(const RayBatch& rays, HitBatch& hits, TraceStats* stats) const {
  const auto tiny = tiny_directions(rays);
  if (tiny.empty()) return intersect_batch(rays, hits, stats);
  intersect_batch(scaled_up(rays, tiny), hits, stats);
  for (const auto& [i, k] : tiny)
    if (hits.prim[i] != kInvalidId) hits.t[i] = std::ldexp(hits.t[i], k);
}

void Accelerator::occluded(const RayBatch& rays, std::vector<uint8_t>& occluded, TraceStats* stats) const {
  const auto tiny = tiny_directions(rays);
  if (tiny.empty()) return occluded_batch(rays, occluded, stats);
  occluded_batch(scaled_up(rays, tiny), occluded, stats);
}

}  // namespace rayscout
