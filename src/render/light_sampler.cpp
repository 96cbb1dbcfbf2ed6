// LightSampler: a power-proportional choice of emissive triangle, then a uniform point on it.
#include "rayscout/render/light_sampler.h"

#include <algorithm>
#include <cmath>

#include "rayscout/core/sampling.h"

namespace rayscout {

LightSampler::LightSampler(const Scene& scene) : scene_(&scene) {
  std::vector<uint32_t> candidates = scene.emissive_triangles;
  if (candidates.empty())  // scenes built by hand may not fill emissive_triangles
    for (uint32_t i = 0; i < scene.triangles.size(); ++i)
      if (scene.material_of(i).emissive()) candidates.push_back(i);
  std::sort(candidates.begin(), candidates.end());  // pdf_area searches them
  std::vector<double> weights;
  for (uint32_t prim : candidates) {
    const Vec3 e = scene.material_of(prim).emission;
    const double w = double(scene.triangles[prim].area()) * (double(e.x) + e.y + e.z) / 3.0;
    if (!(w > 0) || !std::isfinite(w)) continue;
    prims_.push_back(prim);
    weights.push_back(w);
  }
  if (!weights.empty()) choice_ = DiscreteDistribution(weights, 53);
}

LightSample LightSampler::sample(uint64_t choice_bits, float u1, float u2) const {
  const size_t k = choice_.sample_bits(choice_bits);
  const Triangle& tri = scene_->triangles[prims_[k]];
  const auto [b1, b2] = sample_triangle(u1, u2);
  LightSample ls;
  ls.p = tri.v0 * (1.0f - b1 - b2) + tri.v1 * b1 + tri.v2 * b2;
  ls.n = normalize(tri.normal());
  ls.emission = scene_->material_of(prims_[k]).emission;
  ls.choice_probability = choice_.probability(k);
  ls.pdf_area = float(ls.choice_probability / double(tri.area()));
  return ls;
}

float LightSampler::pdf_area(uint32_t prim) const {
  const auto it = std::lower_bound(prims_.begin(), prims_.end(), prim);
  if (it == prims_.end() || *it != prim) return 0.0f;
  return float(choice_.probability(size_t(it - prims_.begin())) / double(scene_->triangles[prim].area()));
}

}  // namespace rayscout
