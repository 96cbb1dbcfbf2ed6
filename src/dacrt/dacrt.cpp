// Dacrt: per-call setup (ray records, triangle boxes, index arrays), task split and results.
#include "rayscout/dacrt/dacrt.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include "dacrt_tracer.h"

namespace rayscout {

using dacrt::RayRecord;

namespace {

// A task below this many rays would lose more to splitting than it gains from a core.
constexpr size_t kMinRaysPerTask = 16384;

size_t task_count(const DacrtConfig& c, size_t n) {
  if (!c.parallel) return 1;
  const size_t threads = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
  return std::max<size_t>(1, std::min(threads, n / kMinRaysPerTask));
}

template <typename F>
void for_range(bool parallel, size_t n, F&& f) {
  if (parallel && n > 65536)
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n), [&](const auto& r) { for (size_t i = r.begin(); i != r.end(); ++i) f(i); });
  else
    for (size_t i = 0; i < n; ++i) f(i);
}

}  // namespace

Dacrt::Dacrt(std::span<const Triangle> triangles, const DacrtConfig& config, std::string name)
    : triangles_(triangles), config_(config), name_(std::move(name)) {}

size_t Dacrt::scratch_bytes(size_t n_rays, size_t n_triangles, size_t tasks) {
  const size_t per_ray = sizeof(RayRecord) + sizeof(RayPrecomp) + 2 * sizeof(uint32_t);  // + rid, scratch
  const size_t per_tri = sizeof(Vec3) + sizeof(Bounds3);
  const size_t per_task = n_triangles * sizeof(uint32_t) +
                          sizeof(dacrt::DacrtTracer<false, false>);  // tid array, binning buffers
  return n_rays * per_ray + n_triangles * per_tri + tasks * per_task;
}

template <bool kOccluded>
void Dacrt::trace(const RayBatch& rays, HitBatch* hits, std::vector<uint8_t>* occluded, TraceStats* stats) const {
  const size_t n = rays.size(), nt = triangles_.size();
  if (kOccluded) occluded->assign(n, 0); else hits->reset(n);
  if (stats) stats->rays += n;
  const size_t tasks = task_count(config_, n);
  last_memory_ = n == 0 ? 0 : scratch_bytes(n, nt, tasks);
  if (n == 0 || nt == 0) return;
  const bool par = config_.parallel;

  // Allocated once per call, sizes from |R|, |T| and the task count only.
  std::vector<RayRecord> rec(n);
  std::vector<RayPrecomp> pre(n, RayPrecomp(Vec3(0, 0, 1)));
  std::vector<uint32_t> rid(n), scratch(n), tid(tasks * nt);
  std::vector<Vec3> centroids(nt);
  std::vector<Bounds3> boxes(nt);
  for_range(par, n, [&](size_t i) {
    const Vec3 d(rays.dx[i], rays.dy[i], rays.dz[i]);
    pre[i] = RayPrecomp(d);
    const Vec3& inv = pre[i].inv_dir;
    rec[i] = {rays.ox[i], rays.oy[i], rays.oz[i], rays.tmin[i], inv.x, inv.y, inv.z, rays.tmax[i]};
    rid[i] = uint32_t(i);
  });
  Bounds3 box, cb;
  for (size_t p = 0; p < nt; ++p) {
    boxes[p] = triangles_[p].bounds();
    centroids[p] = boxes[p].center();
    box.extend(boxes[p]);
    cb.extend(centroids[p]);
  }

  float magnitude = std::max(max_component(abs(box.lo)), max_component(abs(box.hi)));
  for (size_t i = 0; i < n; ++i)
    magnitude = std::max(magnitude, std::max(std::fabs(rays.ox[i]), std::max(std::fabs(rays.oy[i]), std::fabs(rays.oz[i]))));
  dacrt::TraceContext ctx{&config_, rec.data(), pre.data(), triangles_.data(), centroids.data(), boxes.data(),
                          {nullptr, nullptr, nullptr}, nullptr, dacrt::pad_for(magnitude)};
  if constexpr (kOccluded) ctx.occ = occluded->data();
  else ctx.hits = {hits->prim.data(), hits->u.data(), hits->v.data()};

  std::vector<TraceStats> task_stats(tasks);
  std::vector<DacrtDetails> task_details(tasks);
  auto run_task = [&](size_t k) {
    const size_t begin = n * k / tasks, end = n * (k + 1) / tasks;
    uint32_t* my_tid = tid.data() + k * nt;
    std::iota(my_tid, my_tid + nt, 0u);
    auto go = [&](auto tracer) {
      tracer->run(rid.data() + begin, end - begin, my_tid, nt, box, cb);
      task_stats[k] = tracer->stats;
      task_details[k] = tracer->details;
    };
    if (stats) go(std::make_unique<dacrt::DacrtTracer<true, kOccluded>>(ctx, scratch.data() + begin, config_.seed + k));
    else go(std::make_unique<dacrt::DacrtTracer<false, kOccluded>>(ctx, scratch.data() + begin, config_.seed + k));
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
  if (stats) {
    DacrtDetails d;
    for (size_t k = 0; k < tasks; ++k) { *stats += task_stats[k]; d += task_details[k]; }
    last_details_ = d;
  }
}

void Dacrt::intersect(const RayBatch& rays, HitBatch& hits, TraceStats* stats) const {
  trace<false>(rays, &hits, nullptr, stats);
}

void Dacrt::occluded(const RayBatch& rays, std::vector<uint8_t>& occluded, TraceStats* stats) const {
  trace<true>(rays, nullptr, &occluded, stats);
}

}  // namespace rayscout
