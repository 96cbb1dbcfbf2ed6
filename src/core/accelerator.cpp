// Accelerator: the batch entry points every ray tracer shares (directions far from unit length,
// subnormal and non-finite values, then the tracer's own batch loop).
#include "rayscout/core/accelerator.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace rayscout {
namespace {

/// Below FLT_MIN and not zero (NaN: false).
bool subnormal(float x) { return x != 0.0f && std::fabs(x) < FLT_MIN; }
/// Subnormal, infinite or NaN.
bool irregular(float x) { return subnormal(x) | !(std::fabs(x) <= FLT_MAX); }

bool has_irregular(const RayBatch& rays, size_t i) {
  return irregular(rays.dx[i]) | irregular(rays.dy[i]) | irregular(rays.dz[i]) | irregular(rays.ox[i]) |
         irregular(rays.oy[i]) | irregular(rays.oz[i]);
}

/// A direction whose largest component m lies outside [2^-32, 2^32] (and is not 0).
bool far_from_unit(float m) { return (m > 0.0f && m < 0x1p-32f) | (m > 0x1p32f); }

float largest_direction_component(const RayBatch& rays, size_t i) {
  return std::max({std::fabs(rays.dx[i]), std::fabs(rays.dy[i]), std::fabs(rays.dz[i])});
}

/// Traced as is: no irregular value and a direction of moderate length.
bool regular(const RayBatch& rays, size_t i) {
  return !has_irregular(rays, i) & !far_from_unit(largest_direction_component(rays, i));
}

/// A ray that is not traced as is, and how it is traced: scaled by 2^k, or not at all (a miss).
struct Irregular {
  size_t i;
  int k;
  bool miss;
};

/// The rays that are not regular (none almost always: one branch-free pass finds out first).
/// k brings the direction's largest component into [1, 2) when it lies outside [2^-32, 2^32],
/// or when a component is subnormal and the largest below 1 (so that the small ones become
/// normal if they can); else 0. Power-of-two scaling is exact in the watertight and slab tests,
/// and keeps their reciprocals and shear factors normal. It also keeps Embree in its range: it
/// reads a component below 1e-18 as +1e-18 (zero_fix; on a random soup it lost 6 % of the hits
/// of rays 4e-17 long) and refuses one above FLT_LARGE (1.844e18).
/// miss: an infinite or NaN component. A kernel would otherwise answer an infinite one with
/// hits behind the origin (1 / inf turns the shear into 0, and t with it).
std::vector<Irregular> irregular_rays(const RayBatch& rays) {
  bool all_regular = true;
  for (size_t i = 0; i < rays.size(); ++i) all_regular &= regular(rays, i);
  std::vector<Irregular> found;
  if (all_regular) return found;
  for (size_t i = 0; i < rays.size(); ++i) {
    if (regular(rays, i)) continue;
    const Vec3 d(rays.dx[i], rays.dy[i], rays.dz[i]), o(rays.ox[i], rays.oy[i], rays.oz[i]);
    if (!is_finite(d) || !is_finite(o)) {
      found.push_back({i, 0, true});
      continue;
    }
    const float m = max_component(abs(d));
    const bool scale = far_from_unit(m) || ((subnormal(d.x) || subnormal(d.y) || subnormal(d.z)) && m < 1.0f);
    found.push_back({i, scale ? -std::ilogb(m) : 0, false});
  }
  return found;
}

/// rays with those directions scaled by 2^k and tmin, tmax by 2^-k (the same points at the
/// scaled distances), then every value still subnormal set to zero. A subnormal shear factor
/// d / d_kz or coordinate keeps too few bits for the signs of the watertight test (an in-plane
/// ray whose third component was 1.4e-45 hit a triangle 0.05 away), while the slab test's
/// reciprocal of it is infinite, as of zero: as zero, both tests and Embree (which reads
/// subnormals as zero) trace the same ray. A ray to miss gets a NaN direction, which every
/// tracer misses.
RayBatch adjusted(const RayBatch& rays, const std::vector<Irregular>& found) {
  RayBatch out = rays;
  auto flush = [](float x) { return subnormal(x) ? std::copysign(0.0f, x) : x; };
  for (const auto& [i, k, miss] : found) {
    if (miss) {
      out.dx[i] = out.dy[i] = out.dz[i] = std::numeric_limits<float>::quiet_NaN();
      continue;
    }
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
  intersect_with(rays, hits, [&](const RayBatch& r, HitBatch& h) { intersect_batch(r, h, stats); });
}

void Accelerator::occluded(const RayBatch& rays, std::vector<uint8_t>& occluded, TraceStats* stats) const {
  occluded_with(rays, occluded, [&](const RayBatch& r, std::vector<uint8_t>& o) { occluded_batch(r, o, stats); });
}

void Accelerator::intersect_with(const RayBatch& rays, HitBatch& hits,
                                 const std::function<void(const RayBatch&, HitBatch&)>& trace) {
  const auto found = irregular_rays(rays);
  if (found.empty()) return trace(rays, hits);
  trace(adjusted(rays, found), hits);
  for (const auto& [i, k, miss] : found)
    if (k != 0 && hits.prim[i] != kInvalidId) hits.t[i] = std::ldexp(hits.t[i], k);
}

void Accelerator::occluded_with(const RayBatch& rays, std::vector<uint8_t>& occluded,
                                const std::function<void(const RayBatch&, std::vector<uint8_t>&)>& trace) {
  const auto found = irregular_rays(rays);
  if (found.empty()) return trace(rays, occluded);
  trace(adjusted(rays, found), occluded);
}

}  // namespace rayscout
