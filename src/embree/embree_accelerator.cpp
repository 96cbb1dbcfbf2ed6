// EmbreeAccelerator: builds an Embree 3 scene over our triangles and traces batches with it.
#include "rayscout/embree/embree_accelerator.h"

#include <algorithm>
#include <atomic>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <mutex>
#include <stdexcept>

#include <embree3/rtcore.h>
#include <tbb/parallel_for.h>

#include "rayscout/core/stopwatch.h"

namespace rayscout {

EmbreeConfig EmbreeConfig::from_options(const AcceleratorOptions& options) {
  EmbreeConfig c;
  c.robust = options.get_bool("robust", c.robust);
  c.high_quality = options.get_choice("quality", c.high_quality, {{"high", true}, {"medium", false}});
  c.packet = options.get_choice("packet", c.packet, {{"1", 1}, {"16", 16}});
  return c;
}

namespace {

const char* error_name(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE: return "RTC_ERROR_NONE";
    case RTC_ERROR_INVALID_ARGUMENT: return "RTC_ERROR_INVALID_ARGUMENT";
    case RTC_ERROR_INVALID_OPERATION: return "RTC_ERROR_INVALID_OPERATION";
    case RTC_ERROR_OUT_OF_MEMORY: return "RTC_ERROR_OUT_OF_MEMORY";
    case RTC_ERROR_UNSUPPORTED_CPU: return "RTC_ERROR_UNSUPPORTED_CPU";
    case RTC_ERROR_CANCELLED: return "RTC_ERROR_CANCELLED";
    default: return "RTC_ERROR_UNKNOWN";
  }
}

}  // namespace

/// The Embree device and scene, and the first error Embree reported on the device.
struct EmbreeAccelerator::State {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::atomic<int64_t> allocated{0};  // bytes currently held by Embree (memory monitor)
  std::mutex error_mutex;
  std::string error;

  ~State() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
  void open_device();
  void attach_triangles(std::span<const Triangle> triangles, RTCBuildQuality quality);
  void throw_if_error(const char* what) {
    std::lock_guard lock(error_mutex);
    if (const RTCError code = device ? rtcGetDeviceError(device) : RTC_ERROR_NONE; code != RTC_ERROR_NONE && error.empty())
      error = error_name(code);
    if (!error.empty()) throw std::runtime_error(std::string("embree: ") + what + ": " + error);
  }
};

// A device whose errors land in `error` and whose allocations are counted in `allocated`.
void EmbreeAccelerator::State::open_device() {
  device = rtcNewDevice(nullptr);
  if (!device)
    throw std::runtime_error(std::string("embree: rtcNewDevice failed (") + error_name(rtcGetDeviceError(nullptr)) + ")");
  rtcSetDeviceErrorFunction(device, [](void* user, RTCError code, const char* message) {
    auto* st = static_cast<State*>(user);
    std::lock_guard lock(st->error_mutex);
    if (st->error.empty()) st->error = message ? message : error_name(code);
  }, this);
  rtcSetDeviceMemoryMonitorFunction(device, [](void* user, ssize_t bytes, bool /*post*/) {
    static_cast<State*>(user)->allocated += bytes;
    return true;
  }, this);
}

// Geometry 0 of the scene: the triangles with unshared vertices (3 per triangle), so that
// Embree's primID i is our triangle i.
void EmbreeAccelerator::State::attach_triangles(std::span<const Triangle> triangles, RTCBuildQuality quality) {
  // Released on every way out: a geometry left unreleased by a throw kept the device alive.
  const std::unique_ptr<RTCGeometryTy, void (*)(RTCGeometry)> geom(rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE),
                                                                   rtcReleaseGeometry);
  rtcSetGeometryBuildQuality(geom.get(), quality);
  const size_t n = triangles.size();
  auto* verts = static_cast<float*>(
      rtcSetNewGeometryBuffer(geom.get(), RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * n));
  throw_if_error("allocating the vertex buffer");
  auto* index = static_cast<uint32_t*>(
      rtcSetNewGeometryBuffer(geom.get(), RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), n));
  throw_if_error("allocating the index buffer");
  static_assert(sizeof(Triangle) == 9 * sizeof(float));
  std::memcpy(verts, triangles.data(), n * sizeof(Triangle));
  for (uint32_t i = 0; i < 3 * n; ++i) index[i] = i;  // below 2^32: Embree refused a larger vertex buffer
  rtcCommitGeometry(geom.get());
  throw_if_error("committing the geometry");
  rtcAttachGeometryByID(scene, geom.get(), 0);
  throw_if_error("attaching the geometry");
}

namespace {

// Left incoherent (RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT, the default): a batch carries no
// coherence hint (camera, shadow, AO and diffuse rays all come as plain batches), and with
// COHERENT Embree's 16-wide packets take its frustum path and switch to single rays later,
// which suits camera rays only. A hint would need a field in the Accelerator interface.
RTCIntersectContext make_context() {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  return ctx;
}

// What Embree 3's traversal asserts (RayK::valid() and tnear >= 0): origin and direction
// components of magnitude <= FLT_LARGE, tnear >= 0, tfar not NaN. Debian's Embree is built
// with assertions, so handing it any other ray aborts the process; such rays are not traced
// and miss (Embree defines no answer for them). An empty segment (tmin > tmax) is not traced
// either: Embree would return it untouched, and a tfar of -inf would then read as occluded.
constexpr float kEmbreeLarge = 1.844e18f;  // FLT_LARGE of Embree's math/constants.h

inline bool embree_can_trace(const RayBatch& rays, size_t i) {
  auto fits = [](float x) { return std::fabs(x) <= kEmbreeLarge; };  // false for NaN
  auto finite = [](float x) { return std::fabs(x) <= FLT_MAX; };      // false for NaN
  return fits(rays.ox[i]) && fits(rays.oy[i]) && fits(rays.oz[i]) && finite(rays.dx[i]) && finite(rays.dy[i]) &&
         finite(rays.dz[i]) && rays.tmin[i] >= 0.0f && rays.tmin[i] <= rays.tmax[i];  // false for NaN tmax
}

// Embree's ray from ours. Accelerator::intersect and occluded have already brought the
// direction to moderate length (Embree reads a component below 1e-18 as 1e-18).
inline void load_ray(const RayBatch& rays, size_t i, RTCRay& r) {
  r.org_x = rays.ox[i]; r.org_y = rays.oy[i]; r.org_z = rays.oz[i]; r.tnear = rays.tmin[i];
  r.dir_x = rays.dx[i]; r.dir_y = rays.dy[i]; r.dir_z = rays.dz[i]; r.tfar = rays.tmax[i];
  r.time = 0.0f; r.mask = 0xFFFFFFFFu; r.id = 0; r.flags = 0;
}

// Packet p of 16 consecutive rays; lanes past the end and rays Embree cannot trace are masked
// off and hold an empty segment (tfar < tnear), so that every lane is a valid ray.
inline void load_ray16(const RayBatch& rays, size_t p, RTCRay16& r, int valid[16]) {
  const size_t base = p * 16, n = rays.size();
  for (int lane = 0; lane < 16; ++lane) {
    const size_t i = base + lane;
    const bool traced = i < n && embree_can_trace(rays, i);
    valid[lane] = traced ? -1 : 0;
    RTCRay e{};
    if (traced) load_ray(rays, i, e);
    else e.tnear = e.dir_z = 1.0f;  // the segment [1, 0] along +z
    r.org_x[lane] = e.org_x; r.org_y[lane] = e.org_y; r.org_z[lane] = e.org_z; r.tnear[lane] = e.tnear;
    r.dir_x[lane] = e.dir_x; r.dir_y[lane] = e.dir_y; r.dir_z[lane] = e.dir_z; r.tfar[lane] = e.tfar;
    r.time[lane] = 0.0f; r.mask[lane] = 0xFFFFFFFFu; r.id[lane] = 0; r.flags[lane] = 0;
  }
}

// body(ctx, p) for every packet p of 16 consecutive rays of n, in parallel.
template <typename Body>
void for_each_packet(size_t n, const Body& body) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, (n + 15) / 16), [&](const auto& range) {
    RTCIntersectContext ctx = make_context();
    for (size_t p = range.begin(); p != range.end(); ++p) body(ctx, p);
  });
}

// body(ctx, i) for every ray i that Embree can trace, in parallel; the others stay misses.
template <typename Body>
void for_each_traceable_ray(const RayBatch& rays, const Body& body) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 64), [&](const auto& range) {
    RTCIntersectContext ctx = make_context();
    for (size_t i = range.begin(); i != range.end(); ++i)
      if (embree_can_trace(rays, i)) body(ctx, i);
  });
}

}  // namespace

EmbreeAccelerator::EmbreeAccelerator(std::span<const Triangle> triangles, const EmbreeConfig& config)
    : state_(std::make_unique<State>()), config_(config) {
  State& s = *state_;
  // Embree turns on flush-to-zero and denormals-are-zero while it works (rtcNewDevice,
  // rtcCommitScene). Were that this thread's first parallel work, oneTBB would create the
  // thread's arena then and give its settings to every later task of the process: brute, bvh
  // and Embree itself would read subnormal values as zero from then on (a ray with tmax =
  // -1.4e-45 < tmin = 0 was hit at t = 0 after an Embree build, missed without one). Parallel
  // work first creates the arena with this thread's own settings.
  tbb::parallel_for(0, 1, [](int) {});
  s.open_device();
  const auto start = SteadyClock::now();
  const RTCBuildQuality quality = config_.high_quality ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM;
  s.scene = rtcNewScene(s.device);
  if (!s.scene) {  // out of memory; Embree may report it on the thread rather than the device
    s.throw_if_error("creating the scene");
    throw std::runtime_error("embree: rtcNewScene failed");
  }
  rtcSetSceneFlags(s.scene, config_.robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
  rtcSetSceneBuildQuality(s.scene, quality);
  if (!triangles.empty()) s.attach_triangles(triangles, quality);
  const int64_t before_build = s.allocated.load();
  rtcCommitScene(s.scene);
  s.throw_if_error("building the scene");
  info_.build_ms = ms_since(start);
  info_.memory_bytes = size_t(std::max<int64_t>(0, s.allocated.load() - before_build));
}

EmbreeAccelerator::~EmbreeAccelerator() = default;

void EmbreeAccelerator::intersect_batch(const RayBatch& rays, HitBatch& hits, TraceStats* stats) const {
  hits.reset(rays.size());
  RTCScene scene = state_->scene;
  const size_t n = rays.size();
  if (config_.packet == 16) {
    for_each_packet(n, [&](RTCIntersectContext& ctx, size_t p) {
      alignas(64) RTCRayHit16 rh;
      alignas(64) int valid[16];
      load_ray16(rays, p, rh.ray, valid);
      for (int lane = 0; lane < 16; ++lane) rh.hit.geomID[lane] = rh.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect16(valid, scene, &ctx, &rh);
      for (int lane = 0; lane < 16 && p * 16 + lane < n; ++lane)
        if (rh.hit.geomID[lane] != RTC_INVALID_GEOMETRY_ID)
          hits.set(p * 16 + lane, {rh.ray.tfar[lane], rh.hit.primID[lane], rh.hit.u[lane], rh.hit.v[lane]});
    });
  } else {
    for_each_traceable_ray(rays, [&](RTCIntersectContext& ctx, size_t i) {
      RTCRayHit rh;
      load_ray(rays, i, rh.ray);
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene, &ctx, &rh);
      if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID)
        hits.set(i, {rh.ray.tfar, rh.hit.primID, rh.hit.u, rh.hit.v});
    });
  }
  if (stats) stats->rays += n;  // Embree has no work counters
}

void EmbreeAccelerator::occluded_batch(const RayBatch& rays, std::vector<uint8_t>& occluded, TraceStats* stats) const {
  occluded.assign(rays.size(), 0);
  RTCScene scene = state_->scene;
  const size_t n = rays.size();
  // Embree marks an occluded ray by setting tfar to -inf.
  if (config_.packet == 16) {
    for_each_packet(n, [&](RTCIntersectContext& ctx, size_t p) {
      alignas(64) RTCRay16 r;
      alignas(64) int valid[16];
      load_ray16(rays, p, r, valid);
      rtcOccluded16(valid, scene, &ctx, &r);
      for (int lane = 0; lane < 16 && p * 16 + lane < n; ++lane) {
        const size_t i = p * 16 + lane;
        occluded[i] = r.tfar[lane] == -kInfinity;
        // rtcOccluded16 never reports a one-point segment (tmin == tmax) occluded, where
        // rtcOccluded1, rtcIntersect16 and our accelerators find its hit: ask rtcOccluded1.
        if (valid[lane] && rays.tmin[i] == rays.tmax[i]) {
          RTCRay single;
          load_ray(rays, i, single);
          rtcOccluded1(scene, &ctx, &single);
          occluded[i] = single.tfar == -kInfinity;
        }
      }
    });
  } else {
    for_each_traceable_ray(rays, [&](RTCIntersectContext& ctx, size_t i) {
      RTCRay r;
      load_ray(rays, i, r);
      rtcOccluded1(scene, &ctx, &r);
      occluded[i] = r.tfar == -kInfinity;
    });
  }
  if (stats) stats->rays += n;
}

}  // namespace rayscout
