// `path`: path tracing with next-event estimation, pbrt-style maxdepth and Russian roulette,
// wavefront order.
#include <algorithm>

#include "direct_lighting.h"
#include "rayscout/render/renderer.h"

namespace rayscout {
namespace {

class PathIntegrator final : public WavefrontIntegrator {
 public:
  std::string name() const override { return "path"; }

 protected:
  const char* continuation_kind() const override { return "path"; }
  // Emission is counted at hits only after camera and mirror bounces; every other bounce
  // gets its direct light from next-event estimation (no double counting, no MIS).
  void shade(const ShadeContext& ctx, const PathState& state, const Ray& ray, const SurfacePoint& sp,
             ShadeOutput& out) const override {
    const Material& m = ctx.scene->material_of(sp.prim);
    detail::add_specular_emission(state, m, sp, ray, out);
    const int max_depth = ctx.config->max_depth;
    if (ctx.bounce >= max_depth) return;
    const Vec3 wo = -ray.dir;
    if (m.type != Material::Type::Mirror) {
      detail::add_point_light_rays(ctx, state, m, sp, wo, out);
      detail::add_area_light_rays(ctx, state, m, sp, wo, out);
    }
    const PathSampler sampler = ctx.sampler(state);
    const BsdfSample bs =
        sample_bsdf(m, sp.n, wo, sampler.get(kDimBsdf), sampler.get(kDimBsdf + 1), sampler.get(kDimBsdf + 2));
    if (!bs.valid) return;
    // The vertex after the last bounce only adds emission, which a non-mirror bounce ignores.
    if (ctx.bounce + 1 == max_depth && !bs.specular) return;
    Vec3 throughput = state.throughput * bs.weight;
    if (!(max_component(throughput) > 0)) return;
    if (ctx.bounce > ctx.config->rr_depth) {
      // Russian roulette as pbrt-v3's PathIntegrator: go on with probability p = the largest
      // throughput component (at least 0.05, at most 1) and weight by 1 / p, so E is unchanged.
      const float p = std::clamp(max_component(throughput), 0.05f, 1.0f);
      if (sampler.get(kDimRoulette) >= p) return;
      throughput = throughput * (1.0f / p);
    }
    out.continue_path({sp.p, ctx.epsilon, bs.wi, kInfinity}, {state.pixel, state.sample, throughput, bs.specular});
  }
};

}  // namespace

std::unique_ptr<Integrator> make_path_integrator() { return std::make_unique<PathIntegrator>(); }

}  // namespace rayscout
