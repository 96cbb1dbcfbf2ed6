// ShaftsAccelerator: build (BVH, then shaft collection) and classified traversal.
#include "rayscout/shafts/shafts_accelerator.h"

#include <algorithm>
#include <cmath>
#include <mutex>

#include <tbb/parallel_for.h>

#include "entry_box_codec.h"
#include "entry_filter.h"
#include "rayscout/bvh/bvh_accelerators.h"
#include "rayscout/core/stopwatch.h"
#include "ray_sampling.h"

namespace rayscout {

ShaftsAccelerator::Settings ShaftsAccelerator::settings_from_options(const AcceleratorOptions& options, Base base) {
  if (base == Base::Binary) return {ShaftConfig::from_options(options, 2), bvh_config_from_options(options)};
  return {ShaftConfig::from_options(options, kWideWidth), wide_bvh_config_from_options(options)};
}

ShaftsAccelerator::ShaftsAccelerator(const Scene& scene, Base base, const ShaftConfig& config_in,
                                     const BvhBuildConfig& bvh_config)
    : base_(base) {
  const ShaftConfig config = config_in.resolved(base == Base::Binary ? 2 : kWideWidth);
  const auto t0 = SteadyClock::now();
  TreeView tree;
  Bounds3 box;
  if (base_ == Base::Binary) {
    bvh2_ = Bvh2::build(scene.triangles, bvh_config);
    bvh_build_ms_ = ms_since(t0);
    tree = TreeView::from_bvh2(bvh2_, config.walk_levels);
    if (!bvh2_.nodes.empty()) box = bvh2_.nodes[0].bounds;
  } else {
    wide_ = WideBvh::build(scene.triangles, bvh_config);
    bvh_build_ms_ = ms_since(t0);
    tree = TreeView::from_wide(wide_);
    box = wide_.bounds;
  }
  // Sample rays only need their hit distance: trace them with the SIMD wide BVH, also when
  // the lists index the binary one (a temporary collapse of it; same hits). Greedy collapse:
  // the SAH collapse traces them ~10 % faster, but its 26-33 ms collapse cancels that
  // (Conference collection: 692-724 ms with it, 712-722 ms greedy; docs/history/shafts.md).
  WideBvh sampling_bvh;
  if (base_ == Base::Binary && config.wide_sampling) sampling_bvh = WideBvh::from_bvh2(bvh2_, scene.triangles);
  const WideBvh* sampler = base_ == Base::Wide ? &wide_ : (config.wide_sampling ? &sampling_bvh : nullptr);
  auto hit = [this, sampler](const Ray& r) {
    return sampler ? sampler->intersect<false>(r, {}, nullptr) : bvh2_.intersect<false>(r, {}, nullptr);
  };
  if (box.empty()) box = Bounds3{Vec3{0.0f}, Vec3{0.0f}};
  RayBatch prepass;
  if (config.select != ShaftSelect::Occupied) prepass = camera_prepass_rays(scene, hit, config.prepass_width, config.seed);
  // The budget is relative to the tree: for the Bvh2 its nodes and ids, without the
  // triangle copy (which would double the budget, and the build, for -1 to +2.5 points of
  // steps saved on Sibenik; docs/history/shafts.md, session 25).
  const size_t budget_base = base_ == Base::Binary ? bvh2_.tree_bytes() : wide_.memory_bytes();
  collection_ = ShaftCollection::build(tree, box, budget_base, scene.triangles,
                                       [&](const Ray& r) { return hit(r).t; }, prepass, config);
  info_.build_ms = ms_since(t0);
  info_.memory_bytes = bvh_memory_bytes() + collection_.memory_bytes();
}

size_t ShaftsAccelerator::bvh_memory_bytes() const {
  return base_ == Base::Binary ? bvh2_.memory_bytes() : wide_.memory_bytes();
}

namespace {

/// The seeded traversal of either BVH behind the same calls, so that the tracing loop is
/// written once: closest or any hit from start entries (empty = the root), with the ray's
/// RayPrecomp when the caller has made one (nullptr: the BVH makes it), and the interval
/// the traversal box-tests with.
class SeededBvh2 {
 public:
  explicit SeededBvh2(const Bvh2& bvh) : bvh_(bvh) {}
  template <bool Stats>  // Bvh2 makes its own RayPrecomp
  Hit intersect(const Ray& ray, const RayPrecomp*, std::span<const uint32_t> start, TraceStats* stats) const {
    return bvh_.intersect<Stats>(ray, start, stats);
  }
  template <bool Stats>
  bool occluded(const Ray& ray, const RayPrecomp*, std::span<const uint32_t> start, TraceStats* stats) const {
    return bvh_.occluded<Stats>(ray, start, stats);
  }
  CullInterval cull_interval(const Ray& ray) const { return bvh_.cull_interval(ray); }

 private:
  const Bvh2& bvh_;
};

class SeededWide {
 public:
  explicit SeededWide(const WideBvh& bvh) : bvh_(bvh) {}
  template <bool Stats>
  Hit intersect(const Ray& ray, const RayPrecomp* rp, std::span<const uint32_t> start, TraceStats* stats) const {
    return rp ? bvh_.intersect<Stats>(ray, *rp, start, stats) : bvh_.intersect<Stats>(ray, start, stats);
  }
  template <bool Stats>
  bool occluded(const Ray& ray, const RayPrecomp* rp, std::span<const uint32_t> start, TraceStats* stats) const {
    return rp ? bvh_.occluded<Stats>(ray, *rp, start, stats) : bvh_.occluded<Stats>(ray, start, stats);
  }
  CullInterval cull_interval(const Ray& ray) const { return bvh_.cull_interval(ray); }

 private:
  const WideBvh& bvh_;
};

/// A ray whose list has entry boxes: filter the entries, then one seeded traversal.
template <bool Stats, bool Any, class Seeded>
void trace_boxed(const detail::EntryBoxCodec& codec, const Seeded& bvh, const Ray& ray, const Candidates& c, size_t i,
                 HitBatch* hits, std::vector<uint8_t>* occ, TraceStats& local) {
  // Box-test the entries on the BVH's own widened interval (box distances and watertight t
  // round differently) and keep the hit ones: sorted near first for a closest hit; in list
  // order (Algorithm 1's near first along the shaft) for an any hit, which has no use for
  // the exact order (measured: fewer steps and 1-10 % less time than sorting; docs/history/shafts.md,
  // "any hit without the per-ray sort"). rp is made once here and handed to the
  // traversal.
  const RayPrecomp rp(ray.dir);
  const CullInterval cull = bvh.cull_interval(ray);
  uint32_t refs[32];
  float dist[32];
  const int n = detail::filter_entries<!Any>(codec, c, ray.org, rp.inv_dir, cull.near(ray.tmin), cull.far(ray.tmax),
                                       refs, dist);
  if constexpr (Stats) local.ray_box_tests += c.list.size();
  if (n == 0) return;
  // One traversal seeded with the surviving entries, nearest first. (Seeding one subtree at a
  // time and skipping entries beyond the current hit was measured slower: per-call overhead.)
  const std::span<const uint32_t> start(refs, size_t(n));
  if constexpr (Any) {
    (*occ)[i] = bvh.template occluded<Stats>(ray, &rp, start, &local) ? 1 : 0;
  } else {
    const Hit h = bvh.template intersect<Stats>(ray, &rp, start, &local);
    if (h.hit()) hits->set(i, h);
  }
}

/// Every ray of the batch: classified and looked up (use_lists), then traced from its list.
template <bool Stats, bool Any, class Seeded>
void trace_rays(const ShaftCollection& collection, const Seeded& bvh, const RayBatch& rays, HitBatch* hits,
                std::vector<uint8_t>* occ, TraceStats* stats, bool use_lists) {
  std::mutex mutex;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 64), [&](const auto& range) {
    TraceStats local;
    // Lookups are software-pipelined: a ray is classified kFar rays ahead (its entry is
    // prefetched) and looked up kNear rays ahead (its list is prefetched), so the two cache
    // misses of a lookup overlap earlier rays' traversals. Same candidates as lookup(ray).
    constexpr size_t kFar = 8, kNear = 4, kRing = 16;
    struct Slot {
      ShaftCoord coord;
      bool classified = false;
      Candidates c;
    };
    Slot ring[kRing];
    const size_t end = range.end();
    auto classify_ahead = [&](size_t j) {
      Slot& s = ring[j % kRing];
      s.classified = collection.grid().classify(rays[j], s.coord);
      if (s.classified)
        if (const uint32_t* e = collection.entry_address(s.coord)) __builtin_prefetch(e);
    };
    auto lookup_ahead = [&](size_t j) {
      Slot& s = ring[j % kRing];
      s.c = s.classified ? collection.lookup(s.coord) : Candidates{};
      if (!s.c.list.empty()) __builtin_prefetch(s.c.list.data());
      if (s.c.boxes) __builtin_prefetch(s.c.boxes);
    };
    if (use_lists) {
      for (size_t j = range.begin(); j < std::min(range.begin() + kFar, end); ++j) classify_ahead(j);
      for (size_t j = range.begin(); j < std::min(range.begin() + kNear, end); ++j) lookup_ahead(j);
    }
    for (size_t i = range.begin(); i != end; ++i) {
      const Ray ray = rays[i];
      if (use_lists) {
        if (i + kFar < end) classify_ahead(i + kFar);
        if (i + kNear < end) lookup_ahead(i + kNear);
      }
      const Candidates c = use_lists ? ring[i % kRing].c : Candidates{};
      if (c.reaches_nothing) continue;  // a miss without traversal
      if (c.boxes && !c.list.empty()) {
        trace_boxed<Stats, Any>(*collection.entry_codec(), bvh, ray, c, i, hits, occ, local);
        continue;
      }
      if constexpr (Any) {
        (*occ)[i] = bvh.template occluded<Stats>(ray, nullptr, c.list, &local) ? 1 : 0;
      } else {
        const Hit h = bvh.template intersect<Stats>(ray, nullptr, c.list, &local);
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

template <bool Any, class Seeded>
void trace(const ShaftCollection& collection, const Seeded& bvh, const RayBatch& rays, HitBatch* hits,
           std::vector<uint8_t>* occ, TraceStats* stats, bool use_lists) {
  if (stats) trace_rays<true, Any>(collection, bvh, rays, hits, occ, stats, use_lists);
  else trace_rays<false, Any>(collection, bvh, rays, hits, occ, nullptr, use_lists);
}

}  // namespace

// Both public variants go through the base's handling of irregular rays (intersect_with).
void ShaftsAccelerator::intersect(const RayBatch& rays, HitBatch& hits, TraceStats* stats,
                                  bool use_lists) const {
  intersect_with(rays, hits, [&](const RayBatch& r, HitBatch& h) { trace_batch(r, h, stats, use_lists); });
}

void ShaftsAccelerator::occluded(const RayBatch& rays, std::vector<uint8_t>& occluded, TraceStats* stats,
                                 bool use_lists) const {
  occluded_with(rays, occluded, [&](const RayBatch& r, std::vector<uint8_t>& o) { trace_batch(r, o, stats, use_lists); });
}

void ShaftsAccelerator::trace_batch(const RayBatch& rays, HitBatch& hits, TraceStats* stats, bool use_lists) const {
  hits.reset(rays.size());
  if (base_ == Base::Binary) trace<false>(collection_, SeededBvh2(bvh2_), rays, &hits, nullptr, stats, use_lists);
  else trace<false>(collection_, SeededWide(wide_), rays, &hits, nullptr, stats, use_lists);
}

void ShaftsAccelerator::trace_batch(const RayBatch& rays, std::vector<uint8_t>& occluded, TraceStats* stats,
                                    bool use_lists) const {
  occluded.assign(rays.size(), 0);
  if (base_ == Base::Binary) trace<true>(collection_, SeededBvh2(bvh2_), rays, nullptr, &occluded, stats, use_lists);
  else trace<true>(collection_, SeededWide(wide_), rays, nullptr, &occluded, stats, use_lists);
}

void ShaftsAccelerator::intersect_batch(const RayBatch& rays, HitBatch& hits, TraceStats* stats) const {
  trace_batch(rays, hits, stats, true);
}

void ShaftsAccelerator::occluded_batch(const RayBatch& rays, std::vector<uint8_t>& occluded, TraceStats* stats) const {
  trace_batch(rays, occluded, stats, true);
}

}  // namespace rayscout
