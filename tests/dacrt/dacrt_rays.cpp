// Ray sets and option combinations shared by the DACRT tests.
#include "dacrt_rays.h"

#include <cmath>
#include <numbers>
#include <string>

#include "generated_scenes.h"

namespace rayscout::testing {

RayBatch pinhole_rays(const Vec3& eye, const Vec3& look_at, float fov_deg, int width, int height) {
  const Vec3 fwd = normalize(look_at - eye);
  const Vec3 right = normalize(cross(fwd, Vec3(0, 1, 0))), up = cross(right, fwd);
  const float h = std::tan(fov_deg * std::numbers::pi_v<float> / 360.0f), w = h * float(width) / float(height);
  RayBatch rays;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float sx = (2.0f * (x + 0.5f) / width - 1.0f) * w, sy = (1.0f - 2.0f * (y + 0.5f) / height) * h;
      rays.push_back({eye, 0.0f, normalize(fwd + right * sx + up * sy), kInfinity});
    }
  return rays;
}

RayBatch shadow_rays(const RayBatch& primary, const HitBatch& hits, const std::vector<Triangle>& tris,
                     const Vec3& light) {
  RayBatch rays;
  for (size_t i = 0; i < primary.size(); ++i) {
    if (hits.prim[i] == kInvalidId) continue;
    const Ray r = primary[i];
    Vec3 n = normalize(tris[hits.prim[i]].normal());
    if (dot(n, r.dir) > 0) n = -n;
    const Vec3 p = r.org + r.dir * hits.t[i] + n * 1e-4f;
    rays.push_back({p, 0.0f, light - p, 0.9999f});
  }
  return rays;
}

std::vector<Triangle> spheres_on_floor() {
  std::vector<Triangle> tris;
  for (Triangle t : grid(48)) {
    // grid spans [0,1]^2 at z = 0: lay it down as a floor y = 0 over [-4, 4]^2.
    for (Vec3* v : {&t.v0, &t.v1, &t.v2}) *v = Vec3(v->x * 8.0f - 4.0f, 0.0f, v->y * 8.0f - 4.0f);
    tris.push_back(t);
  }
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j)
      for (const Triangle& t : sphere({-3.5f + i, 0.35f, -3.5f + j}, 0.3f, 2)) tris.push_back(t);
  return tris;
}

std::vector<std::vector<std::string>> switch_combinations() {
  std::vector<std::vector<std::string>> combos;
  for (const char* cost : {"cost=sah", "cost=sampled"})
    for (const char* order : {"order=one-ray", "order=sampled"})
      for (const char* skip : {"skip=off", "skip=on"})
        combos.push_back({cost, order, skip, "min_rays=64", "samples=16", "parallel=off"});
  // Samplings, thresholds and the parallel mode on the full method.
  const std::vector<std::string> rs = {"cost=sampled", "order=sampled", "skip=on", "min_rays=64"};
  for (std::vector<std::string> extra : std::vector<std::vector<std::string>>{
           {"strategy=random", "samples=16"}, {"order=literal-votes"}, {"order=sign-votes"}, {"order=interval-votes"}, {"order=interval-votes", "vote_weight=depth"}, {"order=sampled", "sample_budget=0"},
           {"resample=on"}, {"sample_budget=0.05"}, {"fraction=0.01"}, {"fraction=0.1", "strategy=random"},
           {"bins=2", "delta_r=1", "delta_t=2"}, {"bins=256", "delta_r=32", "delta_t=32"},
           {"midpoint_ratio=0"}, {"midpoint_ratio=1000"}, {"C_tri=0.1", "C_bv=5"}, {"parallel=on"}}) {
    auto c = rs;
    c.insert(c.end(), extra.begin(), extra.end());
    combos.push_back(c);
  }
  return combos;
}

AcceleratorOptions options_of(const std::vector<std::string>& kv) {
  AcceleratorOptions o;
  for (const auto& s : kv) o.set(s);
  return o;
}

std::string label_of(const std::vector<std::string>& kv) {
  std::string s;
  for (const auto& k : kv) s += (s.empty() ? "" : " ") + k;
  return s;
}

}  // namespace rayscout::testing
