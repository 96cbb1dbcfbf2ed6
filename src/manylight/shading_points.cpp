// Shading points from pinhole camera rays, following mirrors, traced as batches.
#include "rayscout/manylight/shading_points.h"

#include "rayscout/core/input_error.h"
#include "rayscout/render/surface.h"
#include "ray_offset.h"
#include "rng.h"

namespace rayscout {

std::vector<ShadingPoint> generate_shading_points(const Scene& scene, const Accelerator& accel,
                                                  const ManylightConfig& config) {
  if (config.width <= 0 || config.height <= 0 || config.spp <= 0)
    throw InputError("manylight: width, height and spp must be positive");
  const Camera& cam = scene.camera;
  const CameraFrame frame = camera_frame(cam, float(config.width) / float(config.height));
  const size_t n = size_t(config.width) * config.height * config.spp;
  const float offset = manylight_detail::ray_offset(scene);

  std::vector<ShadingPoint> points(n);
  RayBatch rays;
  rays.resize(n);
  std::vector<uint32_t> active(n);
  std::vector<Vec3> throughput(n, Vec3(1.0f / float(config.spp)));
  for (size_t i = 0; i < n; ++i) {
    const uint32_t pixel = uint32_t(i / config.spp);
    const int x = int(pixel % config.width), y = int(pixel / config.width);
    float jx = 0.5f, jy = 0.5f;
    if (config.spp > 1) {
      manylight_detail::Rng rng(config.seed, 0xCA3E, i);
      jx = rng.uniform();
      jy = rng.uniform();
    }
    points[i].pixel = pixel;
    const Vec3 dir = frame.direction((float(x) + jx) / float(config.width), (float(y) + jy) / float(config.height));
    rays.set(i, {cam.eye, 0.0f, dir, kInfinity});
    active[i] = uint32_t(i);
  }
  HitBatch hits;
  for (int bounce = 0; !active.empty(); ++bounce) {
    accel.intersect(rays, hits);
    RayBatch next_rays;
    std::vector<uint32_t> next_active;
    for (size_t k = 0; k < active.size(); ++k) {
      if (!hits[k].hit()) continue;
      ShadingPoint& sp = points[active[k]];
      const Ray ray = rays[k];
      const uint32_t prim = hits.prim[k];
      const Material& m = scene.material_of(prim);
      const Vec3 wo = -normalize(ray.dir);
      Vec3 nrm = normalize(scene.triangles[prim].normal());
      if (dot(nrm, wo) < 0.0f) nrm = -nrm;
      // The render module's hit refinement: t from the triangle itself, so that accelerators whose
      // kernels round differently (Embree) give the same shading points.
      const Vec3 p = ray.org + ray.dir * refine_hit(scene, ray, hits[k]).t;
      Vec3& tp = throughput[active[k]];
      // Emitters are one-sided: they shine on the side of the geometric normal.
      if (m.emissive() && dot(scene.triangles[prim].normal(), ray.dir) < 0.0f) sp.emitted += tp * m.emission;
      if (m.type == Material::Type::Mirror) {
        if (bounce >= config.max_mirror_bounces) continue;
        tp *= m.specular;
        if (max_component(tp) <= 0.0f) continue;
        next_rays.push_back({p + nrm * offset, 0.0f, reflect(-wo, nrm), kInfinity});
        next_active.push_back(active[k]);
        continue;
      }
      sp.position = p;
      sp.normal = nrm;
      sp.wo = wo;
      sp.weight = tp;
      sp.material = scene.material_ids[prim];
    }
    rays = std::move(next_rays);
    active.swap(next_active);
  }
  return points;
}

}  // namespace rayscout
