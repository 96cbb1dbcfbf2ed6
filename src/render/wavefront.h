// WavefrontIntegrator: the batch loop every integrator of rayscout shares.
#pragma once

#include <string>
#include <cstdint>
#include <vector>

#include "rayscout/core/sampling.h"
#include "rayscout/render/bsdf.h"
#include "rayscout/render/light_sampler.h"
#include "rayscout/render/renderer.h"
#include "rayscout/render/sampler.h"
#include "rayscout/render/surface.h"

namespace rayscout {

/// One camera sample's path alive in the wavefront.
struct PathState {
  uint32_t pixel = 0;      ///< y * width + x
  uint32_t sample = 0;     ///< camera sample index in the pixel
  Vec3 throughput{1.0f};
  bool specular = true;    ///< the last bounce was a mirror (or it is the camera ray): emission counts
  /// Solid-angle pdf of the non-mirror bounce that made the ray, when next-event estimation at
  /// that vertex shares area lights with it by MIS (path); 0 = it does not, emission is skipped.
  float bsdf_pdf = 0;

  /// The same camera sample after a bounce: the new throughput, whether the bounce was a
  /// mirror, and its bsdf_pdf (0 unless the vertex shares area lights by MIS).
  PathState after_bounce(const Vec3& new_throughput, bool mirror, float pdf = 0) const {
    return {pixel, sample, new_throughput, mirror, pdf};
  }
};

/// Per-render constants handed to shading.
struct ShadeContext {
  const Scene* scene = nullptr;
  const RenderConfig* config = nullptr;
  const LightSampler* lights = nullptr;
  float epsilon = 0;    ///< offset of rays leaving a surface, see spawn_ray
  float ao_radius = 0;  ///< resolved AO radius
  int bounce = 0;

  /// The random numbers of path s at this bounce.
  PathSampler sampler(const PathState& s) const {
    return {config->seed, s.pixel, s.sample, uint32_t(bounce)};
  }
};

/// What shading one path vertex produces; filled per chunk of paths, merged in chunk order.
class ShadeOutput {
 public:
  /// Radiance reaching the pixel now (emission seen).
  void add_radiance(uint32_t pixel, const Vec3& value) { radiance_.push_back({pixel, value}); }
  /// A shadow/AO ray: `contribution` is added to the pixel when nothing occludes it.
  void add_occlusion_ray(const Ray& ray, uint32_t pixel, const Vec3& contribution) {
    occlusion_rays_.push_back(ray);
    occlusion_.push_back({pixel, contribution});
  }
  /// The path goes on with this ray in the next bounce.
  void continue_path(const Ray& ray, const PathState& state) {
    next_rays_.push_back(ray);
    next_.push_back(state);
  }

 private:
  friend class WavefrontIntegrator;
  void clear() {
    radiance_.clear(); occlusion_.clear(); occlusion_rays_.clear(); next_rays_.clear(); next_.clear();
  }
  struct Contribution { uint32_t pixel; Vec3 value; };
  std::vector<Contribution> radiance_, occlusion_;
  std::vector<Ray> occlusion_rays_, next_rays_;
  std::vector<PathState> next_;
};

/// The wavefront loop: camera rays for every pixel sample as one batch
/// (split into passes of whole samples when above RenderConfig::max_batch_rays, and into
/// bands of rows when even one sample of every pixel is above it);
/// trace the whole batch; shade every hit (chunks in parallel); trace the batch of occlusion
/// rays; continue with the batch of next rays. Contributions are added per pixel in a fixed
/// order (bounce, then path order), so images do not depend on the thread count.
class WavefrontIntegrator : public Integrator {
 public:
  Image render(const Scene& scene, const Accelerator& accel, const RenderConfig& config,
               RenderStats* stats = nullptr) const override;

 protected:
  /// BatchInfo::kind of continuation rays ("mirror", "path").
  virtual const char* continuation_kind() const = 0;
  /// BatchInfo::kind of occlusion rays ("shadow", "ao").
  virtual const char* occlusion_kind() const { return "shadow"; }
  /// Last bounce whose rays are traced (for progress).
  virtual int max_bounce(const RenderConfig& config) const { return config.max_depth; }
  /// Shades the (refined) hit of `ray`, a path vertex at ctx.bounce.
  virtual void shade(const ShadeContext& ctx, const PathState& state, const Ray& ray,
                     const SurfacePoint& sp, ShadeOutput& out) const = 0;
  /// A ray that hit nothing (default: black background).
  virtual void miss(const ShadeContext&, const PathState&, const Ray&, ShadeOutput&) const {}

 private:
  struct Bounce;  // one bounce's batches, reused across bounces (wavefront.cpp)
  void shade_bounce(const ShadeContext& ctx, Bounce& b) const;
  static void merge_bounce(Bounce& b, std::vector<Vec3>& film);
};

/// Light sample k of a path vertex: the renderer's next-event estimation and the shadow workload.
inline LightSample sample_light(const LightSampler& lights, const PathSampler& sampler, int k) {
  const uint32_t dim = light_sample_dim(k);
  return lights.sample(sampler.bits(dim), sampler.get(dim + 1), sampler.get(dim + 2));
}

/// BSDF sample of a path vertex: the path integrator's bounce and the diffuse workload.
inline BsdfSample sample_bsdf(const Material& m, const Vec3& n, const Vec3& wo, const PathSampler& sampler) {
  return sample_bsdf(m, n, wo, sampler.get(kDimBsdf), sampler.get(kDimBsdf + 1), sampler.get(kDimBsdf + 2));
}

/// Ambient-occlusion direction k of a path vertex, cosine-distributed around n: the ao
/// integrator and the ao workload.
inline Vec3 sample_ao_direction(const PathSampler& sampler, const Vec3& n, int k) {
  const uint32_t dim = light_sample_dim(k);
  return sample_cosine_hemisphere(n, sampler.get(dim), sampler.get(dim + 1));
}

/// Camera rays of samples [sample_begin, sample_end) of spp (sample_end < 0: to spp) of the
/// pixels of rows [row_begin, row_end) (row_end < 0: to height), pixel-major with samples
/// inner; paths gets the matching states. Shared with make_workload.
void generate_camera_rays(const Scene& scene, int width, int height, int spp, uint64_t seed,
                          RayBatch& rays, std::vector<PathState>* paths, int sample_begin = 0,
                          int sample_end = -1, int row_begin = 0, int row_end = -1);

/// The error for width x height x spp camera samples beyond 32-bit sample ids, with the values
/// (it said only "width * height * spp must stay below 2^32"); `what` is "render" or "workload".
std::string samples_beyond_32_bits(const char* what, int width, int height, int spp);

}  // namespace rayscout
