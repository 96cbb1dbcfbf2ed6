// Rendering: configuration, per-batch hooks, statistics and the Integrator interface.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "rayscout/core/accelerator.h"
#include "rayscout/core/ray.h"
#include "rayscout/core/trace_stats.h"
#include "rayscout/image/image.h"
#include "rayscout/scene/scene.h"

namespace rayscout {

/// What a ray batch is, handed to RenderConfig::on_batch before the batch is traced.
struct BatchInfo {
  /// Wavefront iteration: 0 = the camera rays and the shadow / AO rays of their hits; k = the
  /// rays continuing from the hits of iteration k - 1 and the shadow rays of their own hits.
  int bounce = 0;
  std::string kind;        ///< "primary", "shadow", "mirror", "ao" or "path"
  bool occlusion = false;  ///< traced with occluded() (any hit) rather than intersect()
};

/// Progress after each traced batch (for a progress bar).
struct RenderProgress {
  int bounce = 0;            ///< bounce of the batch just traced
  int max_depth = 0;         ///< the last bounce that can occur
  int pass = 0, passes = 1;  ///< sample pass (see RenderConfig::max_batch_rays)
  uint64_t rays_traced = 0;  ///< all rays so far
  double elapsed_s = 0;
};

/// Everything that controls a render. Same config and seed -> the same image, bit for bit,
/// for any thread count and on every accelerator whose hits are bit-identical to brute force
/// (all of rayscout's; embree's distances differ in the last bits, and so may its images).
struct RenderConfig {
  int width = 512, height = 512;
  int spp = 4;             ///< camera samples per pixel, stratified
  uint64_t seed = 1;
  int max_depth = 3;       ///< path: bounces (pbrt's maxdepth); direct/area: mirror reflections
  /// path: Russian roulette at the vertices after this many bounces (pbrt-v3's `bounces > 3`):
  /// a path goes on with probability max(0.05, min(1, largest throughput component)) and its
  /// throughput is divided by it; >= max_depth - 1 never plays.
  int rr_depth = 3;
  int light_samples = 1;   ///< area/path: shadow rays to area lights per hit
  int ao_samples = 4;      ///< ao: rays per hit
  float ao_radius = 0;     ///< ao: ray length; 0 = 10% of the scene diagonal
  float ray_epsilon = 0;   ///< offset of rays leaving a surface (spawn_ray); 0 = scene_ray_epsilon(scene bounds)
  bool count = false;      ///< collect TraceStats per batch (slower)
  /// Largest camera batch: above it the samples of each pixel are rendered in passes of whole
  /// samples (each pass a full wavefront), and an image with more pixels than this in bands
  /// of rows (at least one row), one sample per pass; this bounds memory (~200-400 bytes per
  /// path). 0 = 2^24 rays. The image depends on it only through float summation order.
  long max_batch_rays = 0;
  /// max_batch_rays with its default applied.
  size_t camera_batch_limit() const { return max_batch_rays > 0 ? size_t(max_batch_rays) : size_t(1) << 24; }
  /// Throws InputError for sizes and counts out of range (width, height 1..32768, spp
  /// 1..65536, width x height x spp below 2^32, depths >= 0, samples >= 1, ray_epsilon and
  /// ao_radius finite and >= 0, max_batch_rays >= 0).
  void validate() const;
  /// Called with every ray batch before it is traced (benchmarks record the per-bounce ray
  /// sets of the papers' workloads with it).
  std::function<void(const BatchInfo&, const RayBatch&)> on_batch;
  /// Called after every traced batch.
  std::function<void(const RenderProgress&)> on_progress;
};

/// One traced batch.
struct BatchStats {
  BatchInfo info;
  uint64_t rays = 0;
  double trace_ms = 0;
  TraceStats counters;   ///< filled when RenderConfig::count
};

/// Where the time of a render went.
struct RenderStats {
  double raygen_ms = 0;   ///< camera ray generation
  double trace_ms = 0;    ///< sum over batches
  double shading_ms = 0;  ///< shading, secondary ray generation, accumulation
  double total_ms = 0;
  std::vector<BatchStats> batches;

  /// Rays of all batches.
  uint64_t rays() const;
  /// Counters of all batches (zero unless RenderConfig::count).
  TraceStats counters() const;
  /// Rays traced per second of trace time, millions.
  double mrays_per_s() const;
  /// One JSON object: phases, batches, rays, Mrays/s and counters (when counted).
  std::string to_json() const;
};

/// A light transport algorithm that renders a scene through an accelerator's batch interface.
class Integrator {
 public:
  virtual ~Integrator() = default;
  /// Name on the command line, e.g. "direct".
  virtual std::string name() const = 0;
  /// Renders config.width x config.height linear RGB. stats, when non-null, receives timings.
  virtual Image render(const Scene& scene, const Accelerator& accel, const RenderConfig& config,
                       RenderStats* stats = nullptr) const = 0;
};

/// The integrators of this module: primary rays, shadow rays to every point light,
/// mirror reflections up to max_depth, and the emission that camera and mirror rays see.
std::unique_ptr<Integrator> make_direct_integrator();
/// As direct, plus light_samples shadow rays per hit to points on the area lights.
std::unique_ptr<Integrator> make_area_integrator();
/// Ambient occlusion: ao_samples cosine-distributed rays of length ao_radius per primary hit;
/// a pixel is the unoccluded fraction (1 = open).
std::unique_ptr<Integrator> make_ao_integrator();
/// Path tracing up to max_depth bounces with next-event estimation (every point light and
/// light_samples area-light samples per vertex), Russian roulette after rr_depth bounces,
/// diffuse, mirror and glossy materials, thin-lens depth of field from the camera.
std::unique_ptr<Integrator> make_path_integrator();

}  // namespace rayscout
