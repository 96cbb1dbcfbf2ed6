// BruteForce: every ray against every triangle, the reference all accelerators are tested against.
#include <atomic>

#include <tbb/parallel_for.h>

#include "rayscout/core/accelerator.h"

namespace rayscout {

void BruteForce::intersect_batch(const RayBatch& rays, HitBatch& hits, TraceStats* stats) const {
  hits.reset(rays.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size()), [&](const auto& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const Ray ray = rays[i];
      const RayPrecomp rp(ray.dir);
      Hit best;
      best.t = ray.tmax;
      for (uint32_t p = 0; p < triangles_.size(); ++p) {
        float t, u, v;
        if (intersect_triangle(ray.org, rp, triangles_[p], ray.tmin, best.t, t, u, v) &&
            is_closer(t, p, best.t, best.prim))
          best = {t, p, u, v};
      }
      if (best.hit()) hits.set(i, best);
    }
  });
  if (stats) {
    stats->rays += rays.size();
    stats->ray_tri_tests += uint64_t(rays.size()) * triangles_.size();
  }
}

void BruteForce::occluded_batch(const RayBatch& rays, std::vector<uint8_t>& occluded, TraceStats* stats) const {
  occluded.assign(rays.size(), 0);
  std::atomic<uint64_t> tests{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size()), [&](const auto& range) {
    uint64_t local_tests = 0;
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const Ray ray = rays[i];
      const RayPrecomp rp(ray.dir);
      for (const Triangle& tri : triangles_) {
        float t, u, v;
        ++local_tests;
        if (intersect_triangle(ray.org, rp, tri, ray.tmin, ray.tmax, t, u, v)) {
          occluded[i] = 1;
          break;
        }
      }
    }
    tests += local_tests;
  });
  if (stats) {
    stats->rays += rays.size();
    stats->ray_tri_tests += tests;
  }
}

}  // namespace rayscout
