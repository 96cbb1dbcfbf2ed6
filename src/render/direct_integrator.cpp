// `direct` and `area`: point-light (and area-light) shadow rays at every hit, mirror reflections.
#include "direct_lighting.h"
#include "rayscout/render/renderer.h"

namespace rayscout {
namespace {

class DirectIntegrator final : public WavefrontIntegrator {
 public:
  explicit DirectIntegrator(bool area_lights) : area_lights_(area_lights) {}
  std::string name() const override { return area_lights_ ? "area" : "direct"; }

 protected:
  const char* continuation_kind() const override { return "mirror"; }
  void shade(const ShadeContext& ctx, const PathState& state, const Ray& ray, const SurfacePoint& sp,
             ShadeOutput& out) const override {
    const Material& m = ctx.scene->material_of(sp.prim);
    detail::add_emission(ctx, state, m, sp, ray, out);
    const Vec3 wo = -ray.dir;
    if (m.type == Material::Type::Mirror) {
      const Vec3 throughput = state.throughput * m.specular;
      if (ctx.bounce < ctx.config->max_depth && max_component(throughput) > 0)
        out.continue_path(spawn_ray(sp, reflect(ray.dir, sp.n), ctx.epsilon),
                          state.after_bounce(throughput, /*mirror=*/true));
      return;
    }
    detail::add_point_light_rays(ctx, state, m, sp, wo, out);
    if (area_lights_) detail::add_area_light_rays(ctx, state, m, sp, wo, out);
  }

 private:
  bool area_lights_;
};

}  // namespace

std::unique_ptr<Integrator> make_direct_integrator() { return std::make_unique<DirectIntegrator>(false); }
std::unique_ptr<Integrator> make_area_integrator() { return std::make_unique<DirectIntegrator>(true); }

}  // namespace rayscout
