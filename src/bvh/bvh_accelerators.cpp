// The "bvh2" and "bvh" accelerators: build timing and batch tracing in parallel over rays.
#include "rayscout/bvh/bvh_accelerators.h"

#include <atomic>
#include <string>

#include <tbb/parallel_for.h>

#include "rayscout/core/stopwatch.h"

namespace rayscout {
namespace {

// Rays per task: enough to amortise scheduling, small enough to balance incoherent rays.
constexpr size_t kGrain = 256;

// Runs trace(ray_index, stats_or_null) over every ray in parallel; counters are summed per
// task and added once, so they are exact and the uncounted path does no counting at all.
template <class Trace>
void for_each_ray(size_t n, TraceStats* stats, Trace&& trace) {
  if (!stats) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, kGrain), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) trace.template operator()<false>(i, nullptr);
    });
    return;
  }
  std::atomic<uint64_t> steps{0}, boxes{0}, tris{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, kGrain), [&](const auto& r) {
    TraceStats local;
    for (size_t i = r.begin(); i != r.end(); ++i) trace.template operator()<true>(i, &local);
    steps += local.traversal_steps;
    boxes += local.ray_box_tests;
    tris += local.ray_tri_tests;
  });
  stats->rays += n;
  stats->traversal_steps += steps;
  stats->ray_box_tests += boxes;
  stats->ray_tri_tests += tris;
}

// Closest hits of a batch with a Bvh2 or WideBvh (from the root).
template <class Tree>
void intersect_all(const Tree& tree, const RayBatch& rays, HitBatch& hits, TraceStats* stats) {
  hits.reset(rays.size());
  for_each_ray(rays.size(), stats, [&]<bool S>(size_t i, TraceStats* s) {
    const Hit h = tree.template intersect<S>(rays[i], {}, s);
    if (h.hit()) hits.set(i, h);
  });
}

// Any hits of a batch with a Bvh2 or WideBvh (from the root).
template <class Tree>
void occluded_all(const Tree& tree, const RayBatch& rays, std::vector<uint8_t>& occluded, TraceStats* stats) {
  occluded.assign(rays.size(), 0);
  for_each_ray(rays.size(), stats, [&]<bool S>(size_t i, TraceStats* s) {
    occluded[i] = tree.template occluded<S>(rays[i], {}, s) ? 1 : 0;
  });
}

}  // namespace

BvhBuildConfig wide_bvh_default_config() {
  BvhBuildConfig c;
  c.max_leaf_size = 8;
  c.leaf_block = kTriangleBlockWidth;
  c.presplit = 0.1f;
  c.presplit_max_pieces = 2;
  c.collapse = CollapseMethod::Sah;
  return c;
}

BvhBuildConfig bvh_config_from_options(const AcceleratorOptions& options, const BvhBuildConfig& defaults) {
  BvhBuildConfig c = defaults;
  c.bins = int(options.get_int("bins", c.bins, 2, kBvhMaxBins));
  c.max_leaf_size = int(options.get_int("max_leaf_size", c.max_leaf_size, 1, kBvhMaxLeafSize));
  c.traversal_cost = float(options.get_double("traversal_cost", c.traversal_cost));
  c.intersection_cost = float(options.get_double("intersection_cost", c.intersection_cost));
  c.leaf_block = int(options.get_int("leaf_block", c.leaf_block, 1, kBvhMaxLeafSize));
  c.presplit = float(options.get_double("presplit", c.presplit, 0.0, 4.0));
  c.presplit_max_pieces = int(options.get_int("presplit_pieces", c.presplit_max_pieces, 1, kBvhMaxPresplitPieces));
  if (!(c.traversal_cost > 0) || !(c.intersection_cost > 0))
    throw InputError("bvh options traversal_cost and intersection_cost must be positive");
  return c;
}

BvhBuildConfig wide_bvh_config_from_options(const AcceleratorOptions& options) {
  BvhBuildConfig c = bvh_config_from_options(options, wide_bvh_default_config());
  c.collapse = options.get_choice("collapse", c.collapse, {{"greedy", CollapseMethod::Greedy}, {"sah", CollapseMethod::Sah}});
  c.collapse_node_cost = float(options.get_double("collapse_node_cost", c.collapse_node_cost));
  c.collapse_leaf_cost = float(options.get_double("collapse_leaf_cost", c.collapse_leaf_cost));
  c.collapse_block_cost = float(options.get_double("collapse_block_cost", c.collapse_block_cost));
  c.collapse_max_leaf = int(options.get_int("collapse_max_leaf", c.collapse_max_leaf, 1, kBvhMaxLeafSize));
  if (!(c.collapse_node_cost > 0) || !(c.collapse_leaf_cost >= 0) || !(c.collapse_block_cost > 0))
    throw InputError("bvh options collapse_node_cost and collapse_block_cost must be positive, collapse_leaf_cost >= 0");
  return c;
}

Bvh2Accelerator::Bvh2Accelerator(std::span<const Triangle> triangles, const BvhBuildConfig& config) {
  info_.build_ms = time_ms([&] { bvh_ = Bvh2::build(triangles, config); });
  info_.memory_bytes = bvh_.memory_bytes();
}

void Bvh2Accelerator::intersect_batch(const RayBatch& rays, HitBatch& hits, TraceStats* stats) const {
  intersect_all(bvh_, rays, hits, stats);
}

void Bvh2Accelerator::occluded_batch(const RayBatch& rays, std::vector<uint8_t>& occluded, TraceStats* stats) const {
  occluded_all(bvh_, rays, occluded, stats);
}

WideBvhAccelerator::WideBvhAccelerator(std::span<const Triangle> triangles, const BvhBuildConfig& config) {
  info_.build_ms = time_ms([&] { bvh_ = WideBvh::build(triangles, config); });
  info_.memory_bytes = bvh_.memory_bytes();
}

void WideBvhAccelerator::intersect_batch(const RayBatch& rays, HitBatch& hits, TraceStats* stats) const {
  intersect_all(bvh_, rays, hits, stats);
}

void WideBvhAccelerator::occluded_batch(const RayBatch& rays, std::vector<uint8_t>& occluded, TraceStats* stats) const {
  occluded_all(bvh_, rays, occluded, stats);
}

}  // namespace rayscout
