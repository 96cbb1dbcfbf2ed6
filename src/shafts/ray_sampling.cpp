// Ray-sampling pre-pass from the scene camera.
#include "ray_sampling.h"

#include <algorithm>
#include <string>

#include "rayscout/core/machine_memory.h"
#include "rayscout/core/random.h"
#include "rayscout/core/sampling.h"

namespace rayscout {
namespace {

/// A cosine-distributed direction around n from the pre-pass's one SplitMix64 stream.
Vec3 cosine_direction(const Vec3& n, SplitMix64& rng) {
  const float u1 = rng.uniform(), u2 = rng.uniform();
  return sample_cosine_hemisphere(n, u1, u2);
}

}  // namespace

RayBatch camera_prepass_rays(const Scene& scene, const std::function<Hit(const Ray&)>& trace,
                             int width, unsigned seed) {
  RayBatch out;
  if (scene.triangles.empty() || width < 1) return out;
  const int height = std::max(1, width * 3 / 4);
  // Up to 1 + 2 (1 + lights) rays a pixel, 32 bytes each, twice while the batch grows: refused
  // before the work (prepass_width 16384 asked for ~25 GB and the kernel killed the process).
  const double pixels = double(width) * double(height);
  const size_t per_pixel = 1 + 2 * (1 + std::min<size_t>(4, scene.point_lights.size()));
  require_memory(pixels * double(per_pixel) * 64.0,
                 "shafts pre-pass: prepass_width " + std::to_string(width) + " (" + std::to_string(size_t(pixels)) +
                     " pixels, up to " + std::to_string(per_pixel) + " rays each at 32 bytes, twice while growing) needs");
  const Camera& cam = scene.camera;
  const CameraFrame frame = camera_frame(cam, float(width) / float(height));
  const float eps = 1e-4f * length(scene.bounds().diagonal());
  SplitMix64 rng{uint64_t(seed) * kGolden64 + 7};
  auto spawn_at = [&](const Ray& ray, const Hit& h) {
    const Vec3 p = ray.org + ray.dir * h.t;
    Vec3 n = normalize(scene.triangles[h.prim].normal());
    if (dot(n, ray.dir) > 0.0f) n = -n;
    Ray d{p, eps, cosine_direction(n, rng), kInfinity};
    out.push_back(d);
    for (size_t l = 0; l < std::min<size_t>(4, scene.point_lights.size()); ++l)
      out.push_back(Ray{p, eps, scene.point_lights[l].position - p, 1.0f - 1e-4f});
    return d;
  };
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const Vec3 dir = frame.direction((float(x) + 0.5f) / float(width), (float(y) + 0.5f) / float(height));
      const Ray primary{cam.eye, 0.0f, dir, kInfinity};
      out.push_back(primary);
      const Hit h = trace(primary);
      if (!h.hit()) continue;
      const Ray d = spawn_at(primary, h);
      const Hit h2 = trace(d);
      if (h2.hit()) spawn_at(d, h2);
    }
  return out;
}

}  // namespace rayscout
