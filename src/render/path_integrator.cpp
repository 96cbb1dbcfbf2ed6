// `path`: path tracing with next-event estimation and MIS for area lights, pbrt-style maxdepth and
// Russian roulette, wavefront order.
#include <algorithm>

#include "direct_lighting.h"
#include "rayscout/render/renderer.h"

namespace rayscout {
namespace {

constexpr float kMinSurvival = 0.05f;  // Russian roulette's smallest probability to go on

// Russian roulette with uniform u: the path goes on with probability p and its throughput is
// divided by p, so the expected value is unchanged. p is the largest throughput component
// (pbrt-v4's rule; pbrt-v3 caps it at 0.95), at most 1 and at least kMinSurvival, which bounds
// the 1 / p a surviving path is weighted by. False: the path ends.
bool survives_roulette(Vec3& throughput, float u) {
  const float p = std::clamp(max_component(throughput), kMinSurvival, 1.0f);
  if (u >= p) return false;
  throughput = throughput * (1.0f / p);
  return true;
}

class PathIntegrator final : public WavefrontIntegrator {
 public:
  std::string name() const override { return "path"; }

 protected:
  const char* continuation_kind() const override { return "path"; }
  // Area lights are reached two ways from a non-mirror vertex: next-event estimation and the
  // BSDF-sampled bounce, combined by MIS with the power heuristic (pbrt's PathIntegrator).
  // Point lights and mirrors are delta: next-event estimation only, and emission in full
  // after camera and mirror bounces.
  void shade(const ShadeContext& ctx, const PathState& state, const Ray& ray, const SurfacePoint& sp,
             ShadeOutput& out) const override {
    const Material& m = ctx.scene->material_of(sp.prim);
    detail::add_emission(ctx, state, m, sp, ray, out);
    const int max_depth = ctx.config->max_depth;
    if (ctx.bounce >= max_depth) return;
    const Vec3 wo = -ray.dir;
    // The last bounce traces no bounce ray, whose vertex could only add emission: next-event
    // estimation takes the full weight there, which keeps the estimate unbiased (the weights
    // of every light point still sum to 1) and saves a batch of rays.
    const bool last_bounce = ctx.bounce + 1 == max_depth;
    const bool mirror = m.type == Material::Type::Mirror;
    if (!mirror) {
      detail::add_point_light_rays(ctx, state, m, sp, wo, out);
      detail::add_area_light_rays(ctx, state, m, sp, wo, out, /*mis=*/!last_bounce);
    }
    if (last_bounce && !mirror) return;  // only a mirror bounce goes on from the last vertex
    const PathSampler sampler = ctx.sampler(state);
    const BsdfSample bs = sample_bsdf(m, sp.n, wo, sampler);
    if (!bs.valid) return;
    Vec3 throughput = state.throughput * bs.weight;
    if (!(max_component(throughput) > 0)) return;
    const bool roulette = ctx.bounce > ctx.config->rr_depth;
    if (roulette && !survives_roulette(throughput, sampler.get(kDimRoulette))) return;
    out.continue_path(spawn_ray(sp, bs.wi, ctx.epsilon), state.after_bounce(throughput, bs.specular, bs.pdf));
  }
};

}  // namespace

std::unique_ptr<Integrator> make_path_integrator() { return std::make_unique<PathIntegrator>(); }

}  // namespace rayscout
