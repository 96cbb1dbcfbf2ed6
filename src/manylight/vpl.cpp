// Instant radiosity: light paths from point and area lights, every vertex a VPL.
#include "rayscout/manylight/vpl.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "rayscout/core/discrete_distribution.h"
#include "rayscout/core/input_error.h"
#include "rayscout/core/sampling.h"
#include "rayscout/core/stopwatch.h"
#include "rayscout/manylight/channel_mean.h"
#include "rayscout/render/bsdf.h"
#include "rayscout/render/surface.h"
#include "ray_offset.h"
#include "rng.h"

namespace rayscout {

using manylight_detail::Rng;

namespace {
constexpr float kPi = std::numbers::pi_v<float>;
}  // namespace

Vec3 vpl_intensity(const Vpl& vpl, const Scene& scene, const Vec3& w) {
  switch (vpl.kind) {
    case Vpl::Kind::Point: return vpl.power;
    case Vpl::Kind::Emitter: return vpl.power * (std::max(0.0f, dot(vpl.normal, w)) / kPi);
    case Vpl::Kind::Surface: {
      const float c = dot(vpl.normal, w);
      if (c <= 0.0f) return Vec3(0.0f);
      return vpl.power * eval_bsdf(scene.materials[vpl.material], vpl.normal, w, vpl.wi) * c;
    }
  }
  return Vec3(0.0f);
}

namespace {

/// A light the paths start from: a point light or one emissive triangle.
struct LightSource {
  bool point = false;
  uint32_t index = 0;  // into point_lights or triangles
  float power = 0;     // scalar power (channel mean, channel_mean.h), W
};

/// A light path in flight.
struct LightPathState {
  Vec3 throughput;  // flux carried, W per colour (not yet divided by the path count)
  uint32_t path = 0;
  int bounces = 0;
};

/// The lights with positive power. Throws InputError when a light's power, or all lights'
/// together, overflows float: the VPL fluxes (power / pdf) would be inf or NaN.
std::vector<LightSource> light_sources(const Scene& scene) {
  std::vector<LightSource> lights;
  double total = 0;
  auto add = [&](bool point, uint32_t index, double power) {
    if (!(power <= std::numeric_limits<float>::max()))
      throw InputError("manylight: the power of " + std::string(point ? "point light " : "emissive triangle ") +
                       std::to_string(index) + " overflows float (its " +
                       (point ? "intensity" : "material's emission") + " is too large)");
    // A dark light would get probability 0 (or, alone, divide the cdf by 0: NaN VPLs).
    if (power > 0) lights.push_back({point, index, float(power)});
    total += power;
  };
  for (uint32_t i = 0; i < scene.point_lights.size(); ++i)
    add(true, i, 4.0 * std::numbers::pi * double(channel_mean(scene.point_lights[i].intensity)));
  // One-sided emitters (the side of the geometric normal, as in the render module): pi Le A.
  for (uint32_t id : scene.emissive_triangles)
    add(false, id, std::numbers::pi * double(channel_mean(scene.material_of(id).emission)) * double(scene.triangles[id].area()));
  if (!(total <= std::numeric_limits<float>::max()))
    throw InputError("manylight: the lights' total power overflows float (intensities or emissions too large)");
  return lights;
}

/// The first vertex of a light path: the VPL on the light (chosen with probability pdf), the
/// ray leaving it and the flux that ray carries.
struct PathStart {
  Vpl vpl;
  Ray ray;
  Vec3 flux;
};

PathStart start_path(const Scene& scene, const LightSource& ls, double pdf, float offset, Rng& rng) {
  PathStart s;
  Vpl& v = s.vpl;
  Vec3 dir, org;
  if (ls.point) {
    const PointLight& pl = scene.point_lights[ls.index];
    v.kind = Vpl::Kind::Point;
    v.position = pl.position;
    v.power = pl.intensity * float(1.0 / pdf);
    const float z = 1.0f - 2.0f * rng.uniform(), phi = 2.0f * kPi * rng.uniform();
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    dir = Vec3(r * std::cos(phi), r * std::sin(phi), z);
    org = pl.position;
    s.flux = pl.intensity * float(4.0 * kPi / pdf);
  } else {
    const Triangle& tri = scene.triangles[ls.index];
    const float a = rng.uniform(), b = rng.uniform();
    const auto [b1, b2] = sample_triangle(a, b);
    v.kind = Vpl::Kind::Emitter;
    v.position = tri.v0 * (1.0f - b1 - b2) + tri.v1 * b1 + tri.v2 * b2;
    const Vec3 n = normalize(tri.normal());
    v.normal = n;
    const Vec3 le = scene.material_of(ls.index).emission;
    v.power = le * (kPi * tri.area() / float(pdf));
    const float u1 = rng.uniform(), u2 = rng.uniform();
    dir = sample_cosine_hemisphere(n, u1, u2);
    org = v.position + n * offset;
    s.flux = v.power;  // Le cos / (pdf_area cos / pi) = pi Le A
  }
  s.ray = {org, 0.0f, dir, kInfinity};
  return s;
}

/// A path segment that hit triangle prim at distance t: the VPL there (none on a mirror) goes
/// to vpls; returns true and the next ray when the path scatters and survives Russian roulette.
bool extend_path(const Scene& scene, const ManylightConfig& config, float offset, const Ray& ray, float t,
                 uint32_t prim, LightPathState& st, std::vector<Vpl>& vpls, Ray& next) {
  const Triangle& tri = scene.triangles[prim];
  const uint32_t mat_id = scene.material_ids[prim];
  const Material& m = scene.materials[mat_id];
  const Vec3 p = ray.org + ray.dir * t;
  const Vec3 wi = -normalize(ray.dir);
  Vec3 n = normalize(tri.normal());
  if (dot(n, wi) < 0.0f) n = -n;
  st.bounces++;
  if (m.type != Material::Type::Mirror) {
    Vpl v;
    v.kind = Vpl::Kind::Surface;
    v.position = p;
    v.normal = n;
    v.wi = wi;
    v.power = st.throughput;
    v.material = mat_id;
    vpls.push_back(v);
  }
  if (st.bounces >= config.max_vpl_bounces) return false;
  Rng rng(config.seed, 0x5CA7 + uint64_t(st.bounces), st.path);
  // The renderer's BSDF sampling (symmetric lobes, so the same for light paths); a mirror
  // takes no random numbers.
  float u[3] = {0.0f, 0.0f, 0.0f};
  if (m.type != Material::Type::Mirror)
    for (float& x : u) x = rng.uniform();
  const BsdfSample bs = sample_bsdf(m, n, wi, u[0], u[1], u[2]);
  if (!bs.valid) return false;
  const Vec3 nt = st.throughput * bs.weight;
  // Russian roulette keeps the flux per path roughly constant.
  const float survive = std::min(1.0f, max_component(nt) / std::max(1e-30f, max_component(st.throughput)));
  if (!(survive > 0.0f) || rng.uniform() >= survive) return false;
  st.throughput = nt / survive;
  next = {p + n * (dot(bs.wi, n) > 0 ? offset : -offset), 0.0f, bs.wi, kInfinity};
  return true;
}

}  // namespace

VplSet generate_vpls(const Scene& scene, const Accelerator& accel, const ManylightConfig& config) {
  const auto start = SteadyClock::now();
  VplSet out;
  const std::vector<LightSource> lights = light_sources(scene);
  if (lights.empty() || config.vpl_count == 0) return out;
  std::vector<double> powers(lights.size());
  for (size_t i = 0; i < lights.size(); ++i) powers[i] = lights[i].power;
  // Integer ranges of 53 random bits: pdf is exactly the chance of choosing the light.
  const DiscreteDistribution light_choice(powers, 53);

  const float offset = manylight_detail::ray_offset(scene);
  const size_t target = config.vpl_count;
  // Start small: an eighth of the target in paths, at least 256, but never more than target / 6
  // (a path makes 1-6 VPLs, so a small target is not overshot much). Later batches aim at the
  // remainder.
  size_t batch_paths = std::min(std::max<size_t>(1, target / 6), std::max<size_t>(256, target / 8));
  std::vector<LightPathState> states;
  RayBatch rays;
  HitBatch hits;
  while (out.vpls.size() < target) {
    states.clear();
    rays.clear();
    for (size_t k = 0; k < batch_paths; ++k) {
      const uint32_t path = uint32_t(out.light_paths + k);
      Rng rng(config.seed, 0x11A7, path);
      const size_t li = light_choice.sample_bits(rng.bits64());
      const double pdf = light_choice.probability(li);
      const PathStart s = start_path(scene, lights[li], pdf, offset, rng);
      out.vpls.push_back(s.vpl);
      if (config.max_vpl_bounces > 0) {
        states.push_back({s.flux, path, 0});
        rays.push_back(s.ray);
      }
    }
    out.light_paths += batch_paths;
    // Wavefront: trace every live path one segment, make VPLs, continue the survivors.
    while (!rays.empty()) {
      accel.intersect(rays, hits);
      std::vector<LightPathState> next_states;
      RayBatch next_rays;
      for (size_t i = 0; i < rays.size(); ++i) {
        if (hits.prim[i] == kInvalidId) continue;
        LightPathState st = states[i];
        Ray next;
        // t refined as for shading points (refine_hit): the same VPLs on every accelerator.
        const float t = refine_hit(scene, rays[i], hits[i]).t;
        if (!extend_path(scene, config, offset, rays[i], t, hits.prim[i], st, out.vpls, next)) continue;
        next_states.push_back(st);
        next_rays.push_back(next);
      }
      states.swap(next_states);
      rays = std::move(next_rays);
    }
    const size_t made = out.vpls.size();
    if (made < target) {
      const double per_path = made > 0 ? double(made) / double(out.light_paths) : 1.0;
      batch_paths = size_t(double(target - made) / per_path) + 1;
    }
  }
  const float inv = 1.0f / float(out.light_paths);
  for (auto& v : out.vpls) v.power *= inv;
  out.build_ms = ms_since(start);
  return out;
}

}  // namespace rayscout
