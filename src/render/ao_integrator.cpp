// `ao`: ambient occlusion, the unoccluded fraction of cosine-distributed rays of a fixed length.
#include "rayscout/render/renderer.h"
#include "wavefront.h"

namespace rayscout {
namespace {

class AoIntegrator final : public WavefrontIntegrator {
 public:
  std::string name() const override { return "ao"; }

 protected:
  const char* continuation_kind() const override { return "none"; }
  const char* occlusion_kind() const override { return "ao"; }
  int max_bounce(const RenderConfig&) const override { return 0; }
  void shade(const ShadeContext& ctx, const PathState& state, const Ray&, const SurfacePoint& sp,
             ShadeOutput& out) const override {
    const PathSampler sampler = ctx.sampler(state);
    const int n = ctx.config->ao_samples;
    const Vec3 weight = state.throughput * (1.0f / float(n));
    for (int k = 0; k < n; ++k)
      out.add_occlusion_ray(spawn_ray(sp, sample_ao_direction(sampler, sp.n, k), ctx.epsilon, ctx.ao_radius),
                            state.pixel, weight);
  }
};

}  // namespace

std::unique_ptr<Integrator> make_ao_integrator() { return std::make_unique<AoIntegrator>(); }

}  // namespace rayscout
