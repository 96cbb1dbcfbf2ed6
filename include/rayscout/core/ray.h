// Rays and hits, one at a time and as structure-of-arrays batches.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "rayscout/core/vec3.h"

namespace rayscout {

inline constexpr float kInfinity = std::numeric_limits<float>::infinity();
/// Triangle id of a miss.
inline constexpr uint32_t kInvalidId = 0xFFFFFFFFu;

/// A ray; hits are accepted for tmin <= t <= tmax. The layout matches the ray file.
struct Ray {
  Vec3 org;
  float tmin = 0.0f;
  Vec3 dir;
  float tmax = kInfinity;
};

/// A closest hit: distance t along the (unnormalised) direction, triangle id and barycentrics
/// (the point is (1-u-v) v0 + u v1 + v v2, as in Embree).
struct Hit {
  float t = kInfinity;
  uint32_t prim = kInvalidId;
  float u = 0.0f, v = 0.0f;
  bool hit() const { return prim != kInvalidId; }
};

/// The one tie rule of every accelerator: a candidate replaces the current hit when it is
/// nearer, or equally near with a smaller triangle id. It makes results independent of
/// traversal order, so accelerators and thread counts agree bit for bit.
inline bool is_closer(float t, uint32_t prim, float best_t, uint32_t best_prim) {
  return t < best_t || (t == best_t && prim < best_prim);
}

/// A batch of rays as structure of arrays: what every accelerator traces.
struct RayBatch {
  std::vector<float> ox, oy, oz, tmin, dx, dy, dz, tmax;

  size_t size() const { return ox.size(); }
  bool empty() const { return ox.empty(); }
  void clear() { resize(0); }
  void resize(size_t n) {
    for (auto* a : {&ox, &oy, &oz, &tmin, &dx, &dy, &dz, &tmax}) a->resize(n);
  }
  void reserve(size_t n) {
    for (auto* a : {&ox, &oy, &oz, &tmin, &dx, &dy, &dz, &tmax}) a->reserve(n);
  }
  void push_back(const Ray& r) {
    ox.push_back(r.org.x); oy.push_back(r.org.y); oz.push_back(r.org.z); tmin.push_back(r.tmin);
    dx.push_back(r.dir.x); dy.push_back(r.dir.y); dz.push_back(r.dir.z); tmax.push_back(r.tmax);
  }
  void set(size_t i, const Ray& r) {
    ox[i] = r.org.x; oy[i] = r.org.y; oz[i] = r.org.z; tmin[i] = r.tmin;
    dx[i] = r.dir.x; dy[i] = r.dir.y; dz[i] = r.dir.z; tmax[i] = r.tmax;
  }
  Ray operator[](size_t i) const {
    return {{ox[i], oy[i], oz[i]}, tmin[i], {dx[i], dy[i], dz[i]}, tmax[i]};
  }
};

/// Closest hits of a batch, structure of arrays, index i belongs to ray i.
struct HitBatch {
  std::vector<float> t, u, v;
  std::vector<uint32_t> prim;

  size_t size() const { return t.size(); }
  /// Resizes to n and resets every entry to a miss.
  void reset(size_t n) {
    t.assign(n, kInfinity); u.assign(n, 0.0f); v.assign(n, 0.0f); prim.assign(n, kInvalidId);
  }
  void set(size_t i, const Hit& h) { t[i] = h.t; prim[i] = h.prim; u[i] = h.u; v[i] = h.v; }
  Hit operator[](size_t i) const { return {t[i], prim[i], u[i], v[i]}; }
};

}  // namespace rayscout
