// Accelerator: the batch entry points every ray tracer shares (subnormal values, then the
// tracer's own batch loop).
#include "rayscout/core/accelerator.h"

#include <cfloat>
#include <cmath>
#include <utility>
#include <vector>

namespace rayscout {
namespace {

/// Below FLT_MIN and not zero (NaN: false).
bool subnormal(float x) { return x != 0.0f && std::fabs(x) < FLT_MIN; }

bool has_subnormal(const RayBatch& rays, size_t i) {
  return subnormal(rays.dx[i]) | subnormal(rays.dy[i]) | subnormal(rays.dz[i]) | subnormal(rays.ox[i]) |
         subnormal(rays.oy[i]) | subnormal(rays.oz[i]);
}

/// A ray with a subnormal direction component or origin coordinate, and the k of its scaling.
struct Subnormal {
  size_t i;
  int k;
};

/// The rays with subnormal values (none almost always: one branch-free pass finds out first).
/// k: when a direction component is subnormal and the largest one is below 1, 2^k brings the
/// largest into [1, 2) (exact), so that the small ones become normal if they can; else 0.
std::vector<Subnormal> subnormal_rays(const RayBatch& rays) {
  bool any = false;
  for (size_t i = 0; i < rays.size(); ++i) any |= has_subnormal(rays, i);
  std::vector<Subnormal> found;
  if (!any) return found;
  for (size_t i = 0; i < rays.size(); ++i) {
    if (!has_subnormal(rays, i)) continue;
    const Vec3 d(rays.dx[i], rays.dy[i], rays.dz[i]);
    const float m = max_component(abs(d));
    const bool scale = (subnormal(d.x) || subnormal(d.y) || subnormal(d.z)) && m < 1.0f && !std::isnan(m);
    found.push_back({i, scale ? -std::ilogb(m) : 0});
  }
  return found;
}

/// rays with those directions scaled by 2^k and tmin, tmax by 2^-k (the same points at the
/// scaled distances), then every value still subnormal set to zero. A subnormal shear factor
/// d / d_kz or coordinate keeps too few bits for the signs of the watertight test (an in-plane
/// ray whose third component was 1.4e-45 hit a triangle 0.05 away), while the slab test's
/// reciprocal of it is infinite, as of zero: as zero, both tests and Embree (which reads
/// subnormals as zero) trace the same ray.
RayBatch adjusted(const RayBatch& rays, const std::vector<Subnormal>& found) {
  RayBatch out = rays;
  auto flush = [](float x) { return subnormal(x) ? std::copysign(0.0f, x) : x; };
  for (const auto& [i, k] : found) {
    out.dx[i] = flush(std::ldexp(rays.dx[i], k));
    out.dy[i] = flush(std::ldexp(rays.dy[i], k));
    out.dz[i] = flush(std::ldexp(rays.dz[i], k));
    out.tmin[i] = std::ldexp(rays.tmin[i], -k);
    out.tmax[i] = std::ldexp(rays.tmax[i], -k);
    out.ox[i] = flush(rays.ox[i]);
    out.oy[i] = flush(rays.oy[i]);
    out.oz[i] = flush(rays.oz[i]);
  }
  return out;
}

}  // namespace

void Accelerator::intersect(const RayBatch& rays, HitBatch& hits, TraceStats* stats) const {
  const auto found = subnormal_rays(rays);
  if (found.empty()) return intersect_batch(rays, hits, stats);
  intersect_batch(adjusted(rays, found), hits, stats);
  for (const auto& [i, k] : found)
    if (k != 0 && hits.prim[i] != kInvalidId) hits.t[i] = std::ldexp(hits.t[i], k);
}

void Accelerator::occluded(const RayBatch& rays, std::vector<uint8_t>& occluded, TraceStats* stats) const {
  const auto found = subnormal_rays(rays);
  if (found.empty()) return occluded_batch(rays, occluded, stats);
  occluded_batch(adjusted(rays, found), occluded, stats);
}

}  // namespace rayscout
