// ShaftsAccelerator: build (BVH, then shaft collection) and classified traversal.
#include "rayscout/shafts/shafts_accelerator.h"

#include <chrono>
#include <mutex>

#include <tbb/parallel_for.h>

#include "rayscout/shafts/ray_sampling.h"

namespace rayscout {

ShaftsAccelerator::ShaftsAccelerator(const Scene& scene, Base base, const ShaftConfig& config,
                                     const BvhBuildConfig& bvh_config)
    : triangles_(scene.triangles), base_(base) {
  const auto t0 = std::chrono::steady_clock::now();
  TreeView tree;
  Bounds3 box;
  if (base_ == Base::Binary) {
    bvh2_ = Bvh2::build(triangles_, bvh_config);
    bvh_build_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    tree = TreeView::from_bvh2(bvh2_);
    if (!bvh2_.nodes.empty()) box = bvh2_.nodes[0].bounds;
  } else {
    wide_ = WideBvh::build(triangles_, bvh_config);
    bvh_build_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    tree = TreeView::from_wide(wide_);
    box = wide_.bounds;
  }
  auto hit = [this](const Ray& r) {
    return base_ == Base::Binary ? bvh2_.intersect<false>(r, triangles_, {}, nullptr)
                                 : wide_.intersect<false>(r, {}, nullptr);
  };
  if (box.empty()) box = Bounds3{Vec3{0.0f}, Vec3{0.0f}};
  RayBatch prepass;
  if (config.select == "camera") prepass = camera_prepass_rays(scene, hit, config.prepass_width, config.seed);
  collection_ = ShaftCollection::build(tree, box, bvh_memory_bytes(), triangles_,
                                       [&](const Ray& r) { return hit(r).t; }, prepass, config);
  info_.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  info_.memory_bytes = bvh_memory_bytes() + collection_.memory_bytes();
}

size_t ShaftsAccelerator::bvh_memory_bytes() const {
  return base_ == Base::Binary ? bvh2_.memory_bytes() : wide_.memory_bytes();
}

template <bool Stats, bool Any>
void ShaftsAccelerator::trace(const RayBatch& rays, HitBatch* hits, std::vector<uint8_t>* occ,
                              TraceStats* stats, bool use_lists) const {
  std::mutex mutex;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 64), [&](const auto& range) {
    TraceStats local;
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const Ray ray = rays[i];
      const Candidates c = use_lists ? collection_.lookup(ray) : Candidates{};
      if (c.nothing) continue;  // the shaft reaches no geometry: a miss
      if constexpr (Any) {
        const bool o = base_ == Base::Binary ? bvh2_.occluded<Stats>(ray, triangles_, c.list, &local)
                                             : wide_.occluded<Stats>(ray, c.list, &local);
        (*occ)[i] = o ? 1 : 0;
      } else {
        const Hit h = base_ == Base::Binary ? bvh2_.intersect<Stats>(ray, triangles_, c.list, &local)
                                            : wide_.intersect<Stats>(ray, c.list, &local);
        if (h.hit()) hits->set(i, h);
      }
    }
    if constexpr (Stats) {
      std::lock_guard lock(mutex);
      *stats += local;
    }
  });
  if constexpr (Stats) stats->rays += rays.size();
}

void ShaftsAccelerator::intersect(const RayBatch& rays, HitBatch& hits, TraceStats* stats,
                                  bool use_lists) const {
  hits.reset(rays.size());
  if (stats) trace<true, false>(rays, &hits, nullptr, stats, use_lists);
  else trace<false, false>(rays, &hits, nullptr, nullptr, use_lists);
}

void ShaftsAccelerator::occluded(const RayBatch& rays, std::vector<uint8_t>& occluded, TraceStats* stats,
                                 bool use_lists) const {
  occluded.assign(rays.size(), 0);
  if (stats) trace<true, true>(rays, nullptr, &occluded, stats, use_lists);
  else trace<false, true>(rays, nullptr, &occluded, nullptr, use_lists);
}

void ShaftsAccelerator::intersect(const RayBatch& rays, HitBatch& hits, TraceStats* stats) const {
  intersect(rays, hits, stats, true);
}

void ShaftsAccelerator::occluded(const RayBatch& rays, std::vector<uint8_t>& occluded, TraceStats* stats) const {
  this->occluded(rays, occluded, stats, true);
}

}  // namespace rayscout
