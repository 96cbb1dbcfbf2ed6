// Ray sets per bounce for the DACRT benchmark (own pinhole camera, shading-free secondary rays).
#include "ray_sets.h"

#include <random>
#include <stdexcept>

#include "rayscout/core/sampling.h"
#include "rayscout/render/renderer.h"

namespace rayscout::bench {
namespace {

struct HitPoint {
  Vec3 p, n, d;  // position, geometric normal facing the incoming ray, incoming direction
};

std::vector<HitPoint> hit_points(const Scene& scene, const RayBatch& rays, const HitBatch& hits) {
  std::vector<HitPoint> out;
  for (size_t i = 0; i < rays.size(); ++i) {
    if (hits.prim[i] == kInvalidId) continue;
    const Ray r = rays[i];
    Vec3 n = normalize(scene.triangles[hits.prim[i]].normal());
    if (dot(n, r.dir) > 0) n = -n;
    out.push_back({r.org + r.dir * hits.t[i], n, r.dir});
  }
  return out;
}

RayBatch shadow_rays(const View& view, const std::vector<HitPoint>& pts, float eps, std::mt19937& rng) {
  RayBatch rays;
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  for (const auto& h : pts) {
    const Vec3 o = h.p + h.n * eps;
    if (view.area_light) {
      const Vec3 l = view.area_corner + view.area_u * u01(rng) + view.area_v * u01(rng);
      rays.push_back({o, 0.0f, l - o, 1.0f - 1e-4f});
    } else {
      for (const Vec3& l : view.point_lights) rays.push_back({o, 0.0f, l - o, 1.0f - 1e-4f});
    }
  }
  return rays;
}

}  // namespace

std::vector<RaySet> make_ray_sets(const Scene& scene, const View& view, int width, int height,
                                  const Accelerator& tracer) {
  std::vector<RaySet> sets;
  const Camera& c = view.camera;
  const CameraFrame frame = camera_frame(c, float(width) / float(height));
  RaySet primary{"primary", 0, false, {}};
  primary.rays.reserve(size_t(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const Vec3 dir = frame.direction((float(x) + 0.5f) / float(width), (float(y) + 0.5f) / float(height));
      primary.rays.push_back({c.eye, 0.0f, dir, kInfinity});
    }
  HitBatch hits;
  tracer.intersect(primary.rays, hits);
  const auto pts = hit_points(scene, primary.rays, hits);
  const float diag = length(scene.bounds().diagonal()), eps = 1e-4f * diag;
  std::mt19937 rng(7);
  sets.push_back(std::move(primary));
  if (RayBatch shadow = shadow_rays(view, pts, eps, rng); !shadow.empty()) sets.push_back({"shadow", 0, true, std::move(shadow)});

  if (view.ao) {
    RaySet ao{"ao", 0, true, {}};
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    for (const auto& h : pts) {
      const float u1 = u01(rng), u2 = u01(rng);
      const Vec3 d = sample_cosine_hemisphere(h.n, u1, u2);
      ao.rays.push_back({h.p + h.n * eps, 0.0f, d, 0.1f * diag});
    }
    sets.push_back(std::move(ao));
  }
  if (view.mirror_floor) {
    RaySet mirror{"mirror", 1, false, {}};
    for (const auto& h : pts)
      if (h.n.y > 0.9f && h.p.y < view.mirror_below_y)
        mirror.rays.push_back({h.p + h.n * eps, 0.0f, h.d - h.n * (2.0f * dot(h.d, h.n)), kInfinity});
    HitBatch mh;
    tracer.intersect(mirror.rays, mh);
    const auto mpts = hit_points(scene, mirror.rays, mh);
    sets.push_back(std::move(mirror));
    sets.push_back({"shadow", 1, true, shadow_rays(view, mpts, eps, rng)});
  }
  return sets;
}

std::vector<RaySet> render_ray_sets(const Scene& scene, const View& view, int width, int height,
                                    const Accelerator& tracer) {
  std::unique_ptr<Integrator> integrator;
  if (view.integrator == "direct") integrator = make_direct_integrator();
  else if (view.integrator == "area") integrator = make_area_integrator();
  else if (view.integrator == "path") integrator = make_path_integrator();
  else if (view.integrator == "ao") integrator = make_ao_integrator();
  else throw std::runtime_error("unknown integrator " + view.integrator);
  RenderConfig config;
  config.width = width;
  config.height = height;
  config.spp = 1;
  config.max_depth = view.max_depth;
  std::vector<RaySet> sets;
  config.on_batch = [&](const BatchInfo& info, const RayBatch& rays) {
    if (!rays.empty()) sets.push_back({info.kind, info.bounce, info.occlusion, rays});
  };
  integrator->render(scene, tracer, config);
  return sets;
}

}  // namespace rayscout::bench
