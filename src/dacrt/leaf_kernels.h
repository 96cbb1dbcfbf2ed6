// Leaf kernels of DACRT (NaiveRT of Algorithm 1): every ray of a node against every triangle,
// with core's watertight intersect_triangle and the is_closer tie rule.
#pragma once

#include <cstddef>
#include <cstdint>

#include "rayscout/core/trace_stats.h"
#include "rayscout/core/triangle.h"
#include "ray_record.h"

namespace rayscout::dacrt {

/// Where closest hits go: prim, u, v per ray id (t lives in the RayRecord).
struct HitOut {
  uint32_t* prim;
  float* u;
  float* v;
};

/// Closest hit of rays rid[0, nr) over triangles tid[0, nt). Returns ray-triangle tests.
__attribute__((noinline)) inline uint64_t leaf_intersect(RayRecord* rays, const RayShear* pre, const uint32_t* rid, size_t nr,
                               const Triangle* tris, const uint32_t* tid, size_t nt, HitOut out) {
  for (size_t i = 0; i < nr; ++i) {
    const uint32_t r = rid[i];
    RayRecord& ray = rays[r];
    const Vec3 org(ray.ox, ray.oy, ray.oz);
    const RayPrecomp rp = to_precomp(pre[r]);
    float best_t = ray.t, best_u = 0, best_v = 0;
    uint32_t best = out.prim[r];
    const uint32_t before = best;
    for (size_t j = 0; j < nt; ++j) {
      const uint32_t p = tid[j];
      float t, u, v;
      if (intersect_triangle(org, rp, tris[p], ray.tmin, best_t, t, u, v) && is_closer(t, p, best_t, best)) {
        best_t = t; best = p; best_u = u; best_v = v;
      }
    }
    if (best != before) {
      ray.t = best_t; out.prim[r] = best; out.u[r] = best_u; out.v[r] = best_v;
    }
  }
  return uint64_t(nr) * nt;
}

/// Any hit of rays rid[0, nr) over triangles tid[0, nt); a blocked ray is marked in occ and
/// retired. Returns ray-triangle tests (a ray stops at its first hit; retired rays cost none).
__attribute__((noinline)) inline uint64_t leaf_occluded(RayRecord* rays, const RayShear* pre, const uint32_t* rid, size_t nr,
                              const Triangle* tris, const uint32_t* tid, size_t nt, uint8_t* occ) {
  uint64_t tests = 0;
  for (size_t i = 0; i < nr; ++i) {
    const uint32_t r = rid[i];
    RayRecord& ray = rays[r];
    if (occ[r]) continue;
    const Vec3 org(ray.ox, ray.oy, ray.oz);
    const RayPrecomp rp = to_precomp(pre[r]);
    for (size_t j = 0; j < nt; ++j) {
      float t, u, v;
      ++tests;
      if (intersect_triangle(org, rp, tris[tid[j]], ray.tmin, ray.t, t, u, v)) {
        occ[r] = 1;
        retire(ray);
        break;
      }
    }
  }
  return tests;
}

/// The lanes of a W-wide SIMD leaf test, stored for its scalar steps: per lane the ray id,
/// origin, tmin, the running best t and triangle id, and the test's t, u, v.
template <int W>
struct LeafLanes {
  alignas(64) float ox[W], oy[W], oz[W], tmin[W], best_t[W], t[W], u[W], v[W];
  alignas(64) uint32_t id[W], best_p[W];
};

/// Redoes triangle p for the lanes in `lanes`, whose edge function was exactly zero or whose t
/// was NaN, with core's intersect_triangle (its double-precision paths) and, for closest hit,
/// is_closer.
/// A lane that hits gets t, u, v overwritten. Returns the lanes that hit.
template <bool kAny, int W>
inline uint32_t redo_in_scalar(LeafLanes<W>& lane, uint32_t lanes, const Triangle& tri, uint32_t p,
                               const RayShear* pre) {
  uint32_t hit = 0;
  for (int l = 0; l < W; ++l) {
    if (!((lanes >> l) & 1)) continue;
    float t, u, v;
    if (intersect_triangle(Vec3(lane.ox[l], lane.oy[l], lane.oz[l]), to_precomp(pre[lane.id[l]]), tri, lane.tmin[l],
                           lane.best_t[l], t, u, v) &&
        (kAny || is_closer(t, p, lane.best_t[l], lane.best_p[l]))) {
      hit |= 1u << l;
      lane.t[l] = t; lane.u[l] = u; lane.v[l] = v;
    }
  }
  return hit;
}

/// Writes back the lanes in `changed` after a SIMD leaf: any hit marks occ and retires the
/// ray; closest hit stores the best t (in best_t), triangle id (best_p), u and v.
template <bool kAny, int W>
inline void store_leaf_hits(const LeafLanes<W>& lane, uint32_t changed, RayRecord* rays, HitOut out, uint8_t* occ) {
  for (int l = 0; l < W; ++l) {
    if (!((changed >> l) & 1)) continue;
    const uint32_t r = lane.id[l];
    if (kAny) {
      occ[r] = 1;
      retire(rays[r]);
    } else {
      rays[r].t = lane.best_t[l]; out.prim[r] = lane.best_p[l]; out.u[r] = lane.u[l]; out.v[r] = lane.v[l];
    }
  }
}

}  // namespace rayscout::dacrt
