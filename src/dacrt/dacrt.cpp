// DacrtAccelerator: per-call setup (ray records, triangle boxes, index arrays), task split and
// results.
#include "rayscout/dacrt/dacrt.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <new>
#include <numeric>

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include "dacrt_tracer.h"
#include "ray_setup.h"

namespace rayscout {

using dacrt::RayRecord;

namespace {

// A task below this many rays would lose more to splitting than it gains from a core.
constexpr size_t kMinRaysPerTask = 16384;
// Per-ray set-up loops run in parallel only above this many rays.
constexpr size_t kMinRaysParallelSetup = 4 * kMinRaysPerTask;

size_t task_count(const DacrtConfig& c, size_t n) {
  if (!c.parallel) return 1;
  // The limit may be set above the cores; the arena never runs more threads than its concurrency.
  const size_t threads = std::min(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism),
                                  size_t(tbb::this_task_arena::max_concurrency()));
  return std::max<size_t>(1, std::min(threads, n / kMinRaysPerTask));
}

template <typename F>
void for_range(bool parallel, size_t n, F&& f) {
  if (parallel && n > kMinRaysParallelSetup)
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n), [&](const auto& r) { for (size_t i = r.begin(); i != r.end(); ++i) f(i); });
  else
    for (size_t i = 0; i < n; ++i) f(i);
}

/// Uninitialised, 64-byte aligned storage that only grows.
template <typename T>
class Buffer {
 public:
  T* get(size_t n) {
    if (n > capacity_) {
      data_.reset();
      void* p = std::aligned_alloc(64, (std::max<size_t>(n, 1) * sizeof(T) + 63) & ~size_t(63));
      if (!p) throw std::bad_alloc();
      data_.reset(static_cast<T*>(p));
      capacity_ = n;
    }
    return data_.get();
  }

 private:
  struct Free { void operator()(T* p) const { std::free(p); } };
  std::unique_ptr<T, Free> data_;
  size_t capacity_ = 0;
};

}  // namespace

struct DacrtAccelerator::Arena {
  Buffer<RayRecord> rec;
  Buffer<dacrt::RayShear> shear;
  Buffer<uint32_t> rid, scratch, tid;
  // Triangle boxes, the scene box and the bounds of the boxes' centres, filled once (the
  // triangles never change).
  Buffer<dacrt::TriBox> boxes;
  Buffer<uint8_t> bin_idx;
  Bounds3 box, cb;
  bool triangles_ready = false;

  /// Fills boxes (|tris| entries), box and cb at the first call.
  void prepare_triangles(std::span<const Triangle> tris, dacrt::TriBox* out) {
    if (triangles_ready) return;
    box = cb = Bounds3{};
    for (size_t p = 0; p < tris.size(); ++p) {
      const Bounds3 b = tris[p].bounds();
      out[p] = dacrt::TriBox(b);
      box.extend(b);
      cb.extend(b.center());
    }
    triangles_ready = true;
  }
};

DacrtAccelerator::DacrtAccelerator(std::span<const Triangle> triangles, const DacrtConfig& config,
                                   std::string name)
    : triangles_(triangles), config_(config), name_(std::move(name)), arena_(std::make_unique<Arena>()) {
  config_.validate();
}

DacrtAccelerator::~DacrtAccelerator() = default;

size_t DacrtAccelerator::scratch_bytes(size_t n_rays, size_t n_triangles, size_t tasks) {
  const size_t per_ray = sizeof(RayRecord) + sizeof(dacrt::RayShear) + 2 * sizeof(uint32_t);  // + rid, scratch
  const size_t per_tri = sizeof(dacrt::TriBox);
  const size_t per_task = n_triangles * (sizeof(uint32_t) + sizeof(uint8_t)) +
                          sizeof(dacrt::DacrtTracer<false, false>);  // tid, bin per triangle, binning buffers
  return n_rays * per_ray + n_triangles * per_tri + tasks * per_task;
}

template <bool kOccluded>
void DacrtAccelerator::trace(const RayBatch& rays, HitBatch* hits, std::vector<uint8_t>* occluded,
                             TraceStats* stats) const {
  const size_t n = rays.size(), nt = triangles_.size();
  if (kOccluded) occluded->assign(n, 0); else hits->reset(n);
  if (stats) stats->rays += n;
  const size_t tasks = task_count(config_, n);
  // The bytes of this call's scratch buffers (arena and tracers), reported as its memory and
  // compared by the tests with the formula scratch_bytes. Left out, all small and none per
  // node: the per-block and per-task vectors below, a concurrent call's Arena object, TBB's
  // own allocations and the recursion's stack.
  size_t taken = 0;
  auto take = [&taken]<typename T>(Buffer<T>& buffer, size_t count) {
    taken += count * sizeof(T);
    return buffer.get(count);
  };
  auto report = [&] {
    std::lock_guard guard(last_mutex_);
    last_memory_ = taken;
  };
  if (n == 0 || nt == 0) return report();
  const bool par = config_.parallel;

  // The kept buffers, or (a concurrent call) buffers of this call only.
  std::unique_lock lock(arena_mutex_, std::try_to_lock);
  std::unique_ptr<Arena> own;
  Arena& a = lock.owns_lock() ? *arena_ : *(own = std::make_unique<Arena>());
  RayRecord* rec = take(a.rec, n);
  dacrt::RayShear* shear = take(a.shear, n);
  uint32_t* rid = take(a.rid, n);
  uint32_t* scratch = take(a.scratch, n);
  uint32_t* tid = take(a.tid, tasks * nt);
  uint8_t* bin_idx = take(a.bin_idx, tasks * nt);
  dacrt::TriBox* const boxes = take(a.boxes, nt);
  a.prepare_triangles(triangles_, boxes);
  const Bounds3 box = a.box, cb = a.cb;

  // Ray records, shears and ids in contiguous blocks (one per thread when parallel).
  const size_t blocks = par && n > kMinRaysParallelSetup ? std::min<size_t>(64, n / kMinRaysPerTask) : 1;
  std::vector<float> block_magnitude(blocks, 0.0f);
  auto setup_block = [&](size_t b) {
    block_magnitude[b] = dacrt::setup_rays(rays, n * b / blocks, n * (b + 1) / blocks, rec, shear, rid);
  };
  if (blocks == 1) setup_block(0);
  else tbb::parallel_for(size_t(0), blocks, setup_block);

  // Rays to miss pass every box test, so each would be tested against every triangle: leave
  // them out of rid (their results stay misses). A NaN direction (see Accelerator::intersect),
  // and an empty or NaN segment: [+inf, tmax < +inf] and [tmin > -inf, -inf] would pass the
  // boxes by filter_tmin/filter_tmax, and a NaN tmin is the retired marker.
  auto must_miss = [&](size_t i) {
    return std::isnan(rays.dx[i]) | std::isnan(rays.dy[i]) | std::isnan(rays.dz[i]) | !(rays.tmin[i] <= rays.tmax[i]);
  };
  size_t live = n;
  bool any_miss = false;
  for (size_t i = 0; i < n; ++i) any_miss |= must_miss(i);
  if (any_miss) live = size_t(std::remove_if(rid, rid + n, must_miss) - rid);

  float magnitude = std::max(max_component(abs(box.lo)), max_component(abs(box.hi)));
  for (const float m : block_magnitude) magnitude = std::max(magnitude, m);
  dacrt::TraceContext ctx{&config_, rec, shear, triangles_.data(), boxes,
                          {nullptr, nullptr, nullptr}, nullptr, dacrt::pad_for(magnitude)};
  if constexpr (kOccluded) ctx.occ = occluded->data();
  else ctx.hits = {hits->prim.data(), hits->u.data(), hits->v.data()};

  // One tracer per task on the heap (its binning buffers).
  taken += tasks * (stats ? sizeof(dacrt::DacrtTracer<true, kOccluded>) : sizeof(dacrt::DacrtTracer<false, kOccluded>));
  std::vector<TraceStats> task_stats(tasks);
  std::vector<DacrtStats> task_dacrt_stats(tasks);
  auto run_task = [&](size_t k) {
    const size_t begin = live * k / tasks, end = live * (k + 1) / tasks;
    uint32_t* my_tid = tid + k * nt;
    std::iota(my_tid, my_tid + nt, 0u);
    auto go = [&](auto tracer) {
      tracer->run(rid + begin, end - begin, my_tid, nt, box, cb);
      task_stats[k] = tracer->stats;
      task_dacrt_stats[k] = tracer->dacrt_stats;
    };
    if (stats) go(std::make_unique<dacrt::DacrtTracer<true, kOccluded>>(ctx, scratch + begin, bin_idx + k * nt, config_.seed + k));
    else go(std::make_unique<dacrt::DacrtTracer<false, kOccluded>>(ctx, scratch + begin, bin_idx + k * nt, config_.seed + k));
  };
  if (tasks == 1) {
    run_task(0);
  } else {
    tbb::task_group group;
    for (size_t k = 0; k < tasks; ++k) group.run([&, k] { run_task(k); });
    group.wait();
  }

  if constexpr (!kOccluded)
    for_range(par, n, [&](size_t i) { if (hits->prim[i] != kInvalidId) hits->t[i] = rec[i].t; });
  report();
  if (stats) {
    DacrtStats d;
    for (size_t k = 0; k < tasks; ++k) { *stats += task_stats[k]; d += task_dacrt_stats[k]; }
    std::lock_guard guard(last_mutex_);
    last_stats_ = d;
  }
}

size_t DacrtAccelerator::last_trace_memory_bytes() const {
  std::lock_guard report(last_mutex_);
  return last_memory_;
}

DacrtStats DacrtAccelerator::last_stats() const {
  std::lock_guard report(last_mutex_);
  return last_stats_;
}

void DacrtAccelerator::intersect_batch(const RayBatch& rays, HitBatch& hits,
                                       TraceStats* stats) const {
  trace<false>(rays, &hits, nullptr, stats);
}

void DacrtAccelerator::occluded_batch(const RayBatch& rays, std::vector<uint8_t>& occluded,
                                      TraceStats* stats) const {
  trace<true>(rays, nullptr, &occluded, stats);
}

}  // namespace rayscout
