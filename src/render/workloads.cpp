// make_workload: the papers' ray sets (primary, shadow, AO, diffuse) as ray batches.
#include "rayscout/render/workloads.h"

#include <tbb/parallel_for.h>

#include "rayscout/core/input_error.h"
#include "rayscout/render/light_sampler.h"
#include "rayscout/render/sampler.h"
#include "rayscout/render/surface.h"
#include "wavefront.h"

namespace rayscout {
namespace {

// A workload has a fixed number of shadow rays per hit: a light within 2 eps of the point
// gets a ray that tests nothing (tmax 0 < tmin).
Ray shadow_ray_or_nothing(const SurfacePoint& sp, const Vec3& target, float eps) {
  const auto shadow = shadow_ray_to(sp, target, eps);
  return shadow ? shadow->ray : Ray{sp.p, eps, sp.n, 0.0f};
}

// Shadow rays per primary hit: one per point light, else one to a point sampled on the area
// lights, none in a scene without lights.
size_t shadow_rays_per_hit(const Scene& scene, const LightSampler& lights) {
  if (!scene.point_lights.empty()) return scene.point_lights.size();
  return lights.empty() ? 0 : 1;
}

}  // namespace

Workload parse_workload(const std::string& name) {
  for (const Workload w : kWorkloads)
    if (name == workload_name(w)) return w;
  std::string known;
  for (const std::string& n : workload_names()) known += (known.empty() ? "" : ", ") + n;
  throw InputError("unknown workload '" + name + "' (known: " + known + ")");
}

std::vector<std::string> workload_names() {
  std::vector<std::string> names;
  for (const Workload w : kWorkloads) names.push_back(workload_name(w));
  return names;
}

std::string workload_name(Workload w) {
  switch (w) {
    case Workload::Primary: return "primary";
    case Workload::Shadow: return "shadow";
    case Workload::Ao: return "ao";
    case Workload::Diffuse: return "diffuse";
  }
  return "?";
}

RayBatch make_workload(const Scene& scene, const Accelerator& accel, Workload workload,
                       const WorkloadConfig& config) {
  if (config.width <= 0 || config.height <= 0 || config.spp <= 0)
    throw InputError("workload: width, height and spp must be positive");
  if (uint64_t(config.width) * uint64_t(config.height) * uint64_t(config.spp) > (uint64_t(1) << 32) - 1)
    throw InputError(samples_beyond_32_bits("workload", config.width, config.height, config.spp));
  RayBatch primary;
  std::vector<PathState> paths;
  generate_camera_rays(scene, config.width, config.height, config.spp, config.seed, primary, &paths);
  if (workload == Workload::Primary) return primary;

  HitBatch hits;
  accel.intersect(primary, hits);
  const Bounds3 bounds = scene.bounds();
  const float eps = scene_ray_epsilon(bounds);
  const float ao_radius = ao_radius_for(config.ao_radius, bounds);
  const LightSampler lights(scene);
  const Material lambert;  // the Diffuse workload's material
  const bool to_points = !scene.point_lights.empty();
  const size_t per_hit = workload == Workload::Shadow ? shadow_rays_per_hit(scene, lights) : 1;
  if (per_hit == 0) return RayBatch{};  // the loop below would sample an empty light sampler

  // Output slot of each hit: an exclusive prefix count, so rays keep the primary order.
  const size_t n = primary.size();
  std::vector<size_t> offset(n + 1, 0);
  for (size_t i = 0; i < n; ++i) offset[i + 1] = offset[i] + (hits.prim[i] != kInvalidId ? per_hit : 0);
  RayBatch out;
  out.resize(offset[n]);
  // Every hit gets per_hit rays, so the layout stays fixed: a light behind the surface still
  // gets its full shadow ray (the renderer would skip it; the papers' sets trace it), and a
  // light too close to test gets a zero-length one (shadow_ray_or_nothing).
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) {
      if (hits.prim[i] == kInvalidId) continue;
      const Ray ray = primary[i];
      const SurfacePoint sp = surface_point(scene, ray, refine_hit(scene, ray, hits[i]));
      const PathSampler sampler{config.seed, paths[i].pixel, paths[i].sample, 0};
      size_t o = offset[i];
      switch (workload) {
        case Workload::Primary: break;
        case Workload::Ao:
          out.set(o, spawn_ray(sp, sample_ao_direction(sampler, sp.n, 0), eps, ao_radius));
          break;
        case Workload::Diffuse:  // the bounce the path integrator samples at a Lambert surface
          out.set(o, spawn_ray(sp, sample_bsdf(lambert, sp.n, -ray.dir, sampler).wi, eps));
          break;
        case Workload::Shadow:
          if (to_points) {
            for (const PointLight& light : scene.point_lights)
              out.set(o++, shadow_ray_or_nothing(sp, light.position, eps));
          } else {
            out.set(o, shadow_ray_or_nothing(sp, sample_light(lights, sampler, 0).p, eps));
          }
          break;
      }
    }
  });
  return out;
}

}  // namespace rayscout
