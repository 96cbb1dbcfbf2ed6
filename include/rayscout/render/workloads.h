// Ray workloads of the papers as ray batches: primary, shadow, ambient occlusion, diffuse.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "rayscout/core/accelerator.h"
#include "rayscout/core/ray.h"
#include "rayscout/scene/scene.h"

namespace rayscout {

/// The ray sets the papers measure (ray-sampling DACRT and shaft-culling papers, "workloads").
enum class Workload { Primary, Shadow, Ao, Diffuse };
/// Every workload, in the order of the enum.
inline constexpr Workload kWorkloads[] = {Workload::Primary, Workload::Shadow, Workload::Ao,
                                          Workload::Diffuse};

/// Size and randomness of a workload.
struct WorkloadConfig {
  int width = 1024, height = 1024;
  int spp = 1;           ///< camera samples per pixel (stratified)
  uint64_t seed = 1;
  float ao_radius = 0;   ///< AO ray length; 0 = 10% of the scene diagonal
};

/// Primary rays from the scene camera (pixel-major, samples inner, unit directions).
/// Shadow/Ao/Diffuse rays start at the primary hits (found with `accel`, refined with
/// refine_hit) in the same order; rays of pixels whose primary ray missed are left out.
/// Shadow: one ray to every point light (or, with no point lights, to one point sampled on
/// the area lights; none in a scene without lights), ending epsilon before the light.
/// Ao: one cosine-distributed ray of length ao_radius. Diffuse: one cosine-distributed ray,
/// tmax = inf. Secondary rays start scene_ray_epsilon off the surface (spawn_ray), from the
/// random numbers the renderer uses at bounce 0 (its first light, AO or BSDF sample).
/// Deterministic for a seed, any thread count.
RayBatch make_workload(const Scene& scene, const Accelerator& accel, Workload workload,
                       const WorkloadConfig& config);

/// "primary", "shadow", "ao" or "diffuse"; throws InputError for anything else.
Workload parse_workload(const std::string& name);
/// The name parse_workload accepts.
std::string workload_name(Workload workload);
/// The names of kWorkloads (for a command line's check).
std::vector<std::string> workload_names();

/// Shadow and AO rays ask whether anything is hit (occluded()); primary and diffuse rays want
/// the closest hit (intersect()).
inline bool is_any_hit(Workload workload) { return workload == Workload::Shadow || workload == Workload::Ao; }

}  // namespace rayscout
