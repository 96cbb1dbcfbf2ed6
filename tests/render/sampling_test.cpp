// Sampling building blocks: counter-based random numbers, pixel strata, thin lens, area
// lights, and the glossy BSDF's sampling weights against its value.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>
#include <vector>

#include "rayscout/core/input_error.h"
#include "rayscout/render/bsdf.h"
#include "rayscout/render/camera_rays.h"
#include "rayscout/render/light_sampler.h"
#include "rayscout/render/sampler.h"
#include "rayscout/render/surface.h"
#include "test_scenes.h"

namespace rayscout {
namespace {

TEST(PathSampler, UniformAndDecorrelated) {
  // Mean and variance of U[0,1) over many keys and dimensions; neighbouring keys differ.
  double sum = 0, sum2 = 0, prod = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const PathSampler s(5, uint32_t(i), uint32_t(i % 7), uint32_t(i % 3));
    const float a = s.get(uint32_t(i % 11)), b = s.get(uint32_t(i % 11) + 1);
    ASSERT_GE(a, 0.0f);
    ASSERT_LT(a, 1.0f);
    sum += a; sum2 += double(a) * a; prod += double(a) * b;
  }
  EXPECT_NEAR(sum / n, 0.5, 0.003);             // sd of the mean 0.29 / sqrt(n) = 0.00065
  EXPECT_NEAR(sum2 / n, 1.0 / 3.0, 0.003);
  EXPECT_NEAR(prod / n, 0.25, 0.003);           // independent dimensions
  EXPECT_NE(PathSampler(1, 0, 0, 0).bits(0), PathSampler(2, 0, 0, 0).bits(0));
  EXPECT_NE(PathSampler(1, 0, 0, 0).bits(0), PathSampler(1, 0, 0, 1).bits(0));
  EXPECT_NE(PathSampler(1, 0, 0, 0).bits(0), PathSampler(1, 1, 0, 0).bits(0));
  EXPECT_NE(PathSampler(1, 0, 0, 0).bits(0), PathSampler(1, 0, 1, 0).bits(0));
  EXPECT_NE(PathSampler(1, 0, 0, 0).bits(0), PathSampler(1, 0, 0, 0).bits(1));
  // Pinned: images are reproducible across builds only if the hash never changes.
  EXPECT_EQ(PathSampler(1, 9, 3, 2).bits(4), 0x77ad7e77a25e21ffull);
}

// Every stratum of a pixel gets exactly one sample, for square and non-square counts.
TEST(PixelSamples, OnePerStratum) {
  for (int spp : {1, 4, 9, 16, 3, 5, 8}) {
    const int k = int(std::lround(std::sqrt(double(spp))));
    const bool grid = k * k == spp;
    std::set<std::pair<int, int>> strata;
    std::set<int> xs, ys;
    for (int s = 0; s < spp; ++s) {
      float fx, fy;
      pixel_sample_position(PathSampler(3, 77, uint32_t(s), 0), 5, 9, s, spp, fx, fy);
      ASSERT_GE(fx, 5.0f); ASSERT_LT(fx, 6.0f);
      ASSERT_GE(fy, 9.0f); ASSERT_LT(fy, 10.0f);
      if (grid) strata.insert({int((fx - 5) * k), int((fy - 9) * k)});
      xs.insert(int((fx - 5) * spp));
      ys.insert(int((fy - 9) * spp));
    }
    if (grid) {
      EXPECT_EQ(int(strata.size()), spp) << spp;
    } else {  // N-rooks: every row and column once
      EXPECT_EQ(int(xs.size()), spp) << spp;
      EXPECT_EQ(int(ys.size()), spp) << spp;
    }
  }
}

// Thin lens: rays of one film position leave from points on the lens disk and all meet at
// the focus distance; a pinhole leaves from the eye.
TEST(CameraRays, ThinLensFocusesOnThePlaneInFocus) {
  Camera cam;
  cam.eye = {1, 2, 3};
  cam.look_at = {1, 2, -7};
  cam.lens_radius = 0.2f;
  cam.focus_distance = 4.0f;
  const CameraRays rays(cam, 64, 48);
  Vec3 meet{0.0f};
  for (int i = 0; i < 16; ++i) {
    const Ray r = rays.generate(20.5f, 30.25f, (i % 4 + 0.5f) / 4, (i / 4 + 0.5f) / 4);
    EXPECT_LE(length(r.org - cam.eye), 0.2f * 1.0001f);
    EXPECT_NEAR(r.org.z, 3.0f, 1e-6f);  // the lens lies in the plane facing the view axis
    EXPECT_NEAR(length(r.dir), 1.0f, 1e-5f);
    const Vec3 p = r.org + r.dir * ((-1.0f - r.org.z) / r.dir.z);  // on the plane z = 3 - 4
    if (i == 0) meet = p;
    EXPECT_LT(length(p - meet), 1e-4f);
  }
  cam.lens_radius = 0;
  EXPECT_EQ(CameraRays(cam, 64, 48).generate(3, 4, 0.9f, 0.1f).org, cam.eye);
  // The centre of the film looks at look_at; the top row is up.
  const Ray centre = CameraRays(cam, 64, 48).generate(32, 24, 0, 0);
  EXPECT_NEAR(centre.dir.z, -1.0f, 1e-6f);
  EXPECT_GT(CameraRays(cam, 64, 48).generate(32, 0, 0, 0).dir.y, 0.0f);
}

// Lens points are uniform on the disk of radius R: E[r^2] = R^2 / 2, a quarter of them within
// R / 2, and equal shares in equal angular sectors (a polar map r = u, not sqrt(u), crowds the
// centre: E[r^2] = R^2 / 3, half within R / 2).
TEST(CameraRays, ThinLensSamplesTheDiskUniformly) {
  Camera cam;
  cam.eye = {1, 2, 3};
  cam.look_at = {1, 2, -7};  // lens plane z = 3, axes x and y
  cam.lens_radius = 0.5f;
  cam.focus_distance = 4.0f;
  const CameraRays rays(cam, 64, 48);
  const int n = 200;  // an n x n grid of (u, v): the disk map's quadrature
  double r2 = 0, inner = 0;
  std::vector<double> sector(8, 0.0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const Ray r = rays.generate(20.5f, 30.25f, (i + 0.5f) / n, (j + 0.5f) / n);
      const double dx = (r.org.x - cam.eye.x) / cam.lens_radius, dy = (r.org.y - cam.eye.y) / cam.lens_radius;
      const double rr = dx * dx + dy * dy;
      ASSERT_LE(rr, 1.0 + 1e-5);
      r2 += rr;
      inner += rr < 0.25;
      const double phi = std::atan2(dy, dx) + std::numbers::pi;
      sector[std::min<size_t>(7, size_t(phi / (2 * std::numbers::pi) * 8))] += 1;
    }
  const double count = double(n) * n;
  EXPECT_NEAR(r2 / count, 0.5, 0.005);
  EXPECT_NEAR(inner / count, 0.25, 0.005);
  for (double c : sector) EXPECT_NEAR(c / count, 0.125, 0.003);
}

// Shirley-Chiu's map at points worked out by hand: the square's ring of half-width 1/2 goes
// to the unit circle, its diagonals to the diagonals, and within each wedge the angle runs
// linearly with the ordinate (pi/8 at (1, 0.75), 3 pi/8 at (0.75, 1)), continuous across the
// diagonals, where the two branches of the map meet.
TEST(ConcentricDisk, KnownPointsOnBothBranchesAndTheDiagonal) {
  const float c = std::cos(std::numbers::pi_v<float> / 8), s = std::sin(std::numbers::pi_v<float> / 8);
  const float h = std::sqrt(0.5f);
  struct Case { float u, v, dx, dy; };
  for (const Case k : {Case{0.5f, 0.5f, 0, 0}, Case{1.0f, 0.75f, c, s}, Case{0.75f, 1.0f, s, c},
                       Case{0.25f, 0.0f, -s, -c}, Case{0.0f, 0.25f, -c, -s}, Case{1.0f, 1.0f, h, h},
                       Case{0.0f, 1.0f, -h, h}, Case{1.0f, 0.5f, 1, 0}, Case{0.5f, 1.0f, 0, 1}}) {
    float dx, dy;
    concentric_disk(k.u, k.v, dx, dy);
    EXPECT_NEAR(dx, k.dx, 1e-6f) << k.u << " " << k.v;
    EXPECT_NEAR(dy, k.dy, 1e-6f) << k.u << " " << k.v;
  }
}

// The ray epsilon is 1e-5 of the larger of the scene's diagonal and its largest coordinate
// magnitude (floats are coarser far from the origin), at every scale (FLT_MIN for a point); the
// AO radius 10 % of the diagonal unless configured.
TEST(SceneScales, RayEpsilonAndAoRadiusFromTheBounds) {
  const Bounds3 box{{0, 0, 0}, {3, 4, 12}};  // diagonal 13
  EXPECT_FLOAT_EQ(scene_ray_epsilon(box), 1e-5f * 13.0f);
  EXPECT_FLOAT_EQ(scene_ray_epsilon({{-1001, -1001, -1001}, {-1000, -1000, -1000}}), 1e-5f * 1001.0f);
  EXPECT_FLOAT_EQ(scene_ray_epsilon({{1000, 0, 0}, {1001, 1, 1}}), 1e-5f * 1001.0f);
  EXPECT_FLOAT_EQ(scene_ray_epsilon({{0, 0, 0}, {3e-8f, 4e-8f, 12e-8f}}), 1e-5f * 13e-8f);
  EXPECT_EQ(scene_ray_epsilon({{0, 0, 0}, {0, 0, 0}}), std::numeric_limits<float>::min());
  EXPECT_FLOAT_EQ(scene_ray_epsilon(Bounds3{}), 1e-5f);
  EXPECT_FLOAT_EQ(ao_radius_for(0.0f, box), 1.3f);
  EXPECT_EQ(ao_radius_for(2.5f, box), 2.5f);
  EXPECT_EQ(ao_radius_for(0.0f, Bounds3{}), 1.0f);
}

// A ray leaving a surface starts `offset` off it along the geometric normal, on the side it
// leaves to, with tmin 0 (so a wall nearer than the offset is still hit). A shadow ray also
// ends `offset` before its target; a target within 2 offsets gets none.
TEST(SceneScales, SpawnedRaysStartOffTheSurfaceOnTheSideTheyLeaveTo) {
  SurfacePoint sp;
  sp.p = {1, 2, 3};
  sp.n_geometric = {0, 0, 1};
  sp.n = {0, 0, -1};  // seen from below: the offset follows the direction, not the viewer
  const Ray up = spawn_ray(sp, {0, 0.6f, 0.8f}, 0.5f, 7.0f);
  EXPECT_EQ(up.org, Vec3(1, 2, 3.5f));
  EXPECT_EQ(up.dir, Vec3(0, 0.6f, 0.8f));
  EXPECT_EQ(up.tmin, 0.0f);
  EXPECT_EQ(up.tmax, 7.0f);
  const Ray down = spawn_ray(sp, {0.6f, 0, -0.8f}, 0.5f);
  EXPECT_EQ(down.org, Vec3(1, 2, 2.5f));
  EXPECT_EQ(down.tmax, kInfinity);

  const auto shadow = shadow_ray_to(sp, {1, 2, 5.5f}, 0.5f);
  ASSERT_TRUE(shadow.has_value());
  EXPECT_EQ(shadow->dist, 2.5f);  // from the surface point, for shading
  EXPECT_EQ(shadow->wi, Vec3(0, 0, 1));
  EXPECT_EQ(shadow->ray.org, Vec3(1, 2, 3.5f));
  EXPECT_EQ(shadow->ray.dir, Vec3(0, 0, 1));
  EXPECT_EQ(shadow->ray.tmin, 0.0f);
  EXPECT_EQ(shadow->ray.tmax, 1.5f);  // 2 from the offset origin, minus the offset
  const auto below = shadow_ray_to(sp, {1, 2, 0}, 0.5f);
  ASSERT_TRUE(below.has_value());
  EXPECT_EQ(below->ray.org, Vec3(1, 2, 2.5f));
  EXPECT_EQ(below->ray.tmax, 2.0f);
  EXPECT_FALSE(shadow_ray_to(sp, {1, 2, 4}, 0.5f).has_value());  // dist 1 = 2 offsets
  EXPECT_FALSE(shadow_ray_to(sp, sp.p, 0.5f).has_value());
}

// A focus plane far away, a lens far wider than the focus distance, a focus distance of
// 1e-30: every ray is still a unit direction from its lens point through the point in focus
// (the lens-to-focus vector once overflowed to inf and gave a black image).
TEST(CameraRays, ExtremeThinLensesStayFinite) {
  Camera cam;
  cam.eye = {0, 0, 5};
  cam.look_at = {0, 0, 0};
  for (auto [radius, focus] : {std::pair{0.1f, 1e30f}, std::pair{1e18f, 1.0f}, std::pair{1.0f, 1e-30f}}) {
    cam.lens_radius = radius;
    cam.focus_distance = focus;
    const CameraRays rays(cam, 8, 8);
    const Ray pinhole = CameraRays(Camera{.eye = cam.eye, .look_at = cam.look_at}, 8, 8).generate(1.5f, 6.5f, 0, 0);
    // The point in focus is eye + pinhole.dir * k, k = focus / cos (view axis -z); its offset
    // from a ray's origin is (eye - org) + pinhole.dir * k, in double.
    const double k = double(focus) / -double(pinhole.dir.z);
    for (float u : {0.1f, 0.5f, 0.9f}) {
      const Ray r = rays.generate(1.5f, 6.5f, u, 1 - u);
      ASSERT_TRUE(is_finite(r.dir) && is_finite(r.org)) << radius << " " << focus;
      EXPECT_NEAR(length(r.dir), 1.0f, 1e-6f);
      const double tx = (0.0 - r.org.x) + k * pinhole.dir.x, ty = (0.0 - r.org.y) + k * pinhole.dir.y,
                   tz = (5.0 - r.org.z) + k * pinhole.dir.z;
      const double len = std::sqrt(tx * tx + ty * ty + tz * tz);
      const double cosine = (tx * r.dir.x + ty * r.dir.y + tz * r.dir.z) / len;
      EXPECT_GT(cosine, 1.0 - 1e-6) << "lens " << radius << " focus " << focus << " u " << u;
    }
  }
  cam.focus_distance = 0;
  EXPECT_THROW(CameraRays(cam, 8, 8), InputError);
}

// The camera's frame depends on the directions of look_at - eye and up, not their lengths.
TEST(CameraFrame, LengthsDoNotMatter) {
  const Camera unit{.eye = {0, 0, 0}, .look_at = {0.6f, 0, -0.8f}, .up = {0, 1, 0}};
  const CameraFrame ref = camera_frame(unit, 2.0f);
  for (float s : {1e-30f, 1e-7f, 1e17f}) {
    const Camera scaled{.eye = {0, 0, 0}, .look_at = unit.look_at * s, .up = {0, s, 0}};
    const CameraFrame f = camera_frame(scaled, 2.0f);
    EXPECT_NEAR(dot(f.forward, ref.forward), 1.0f, 1e-6f) << s;
    EXPECT_NEAR(dot(f.right, ref.right), 1.0f, 1e-6f) << s;
    EXPECT_NEAR(dot(f.up, ref.up), 1.0f, 1e-6f) << s;
  }
  EXPECT_NEAR(ref.half_w, 2.0f * ref.half_h, 1e-6f);
  EXPECT_NEAR(ref.half_h, std::tan(0.5f * 60.0f * 3.14159265f / 180.0f), 1e-6f);
  // A short up that is not parallel is the user's up, not a substitute.
  const CameraFrame sideways = camera_frame({.eye = {0, 0, 1}, .look_at = {0, 0, 0}, .up = {1e-7f, 0, 0}}, 1.0f);
  EXPECT_NEAR(sideways.up.x, 1.0f, 1e-6f);
  EXPECT_THROW(camera_frame({.eye = {0, 0, 1}, .look_at = {0, 0, 0}, .up = {1e-7f, 0, 1}}, 1.0f), InputError);
  EXPECT_THROW(camera_frame({.eye = {1, 2, 3}, .look_at = {1, 2, 3}}, 1.0f), InputError);
  EXPECT_THROW(CameraRays(Camera{.eye = {0, 1, 0}, .look_at = {0, 0, 0}}, 4, 4), InputError);
}

// Triangles are chosen in proportion to area x emission; pdf_area integrates to 1.
TEST(LightSampler, PowerProportionalChoice) {
  Scene scene;
  testing::add_part(scene, testing::quad({0, 0, 0}, {1, 0, 0}, {0, 1, 0}), Material{.emission = Vec3{1.0f}});
  testing::add_part(scene, testing::quad({5, 0, 0}, {2, 0, 0}, {0, 1, 0}), Material{.emission = Vec3{3.0f}});
  testing::add_part(scene, testing::quad({9, 0, 0}, {1, 0, 0}, {0, 1, 0}), Material{});  // not a light
  const LightSampler lights(scene);
  const int n = 100000;
  int second = 0;
  double inv_pdf = 0;
  for (int i = 0; i < n; ++i) {
    const PathSampler s(1, uint32_t(i), 0, 0);
    const LightSample ls = lights.sample(s.bits(0), s.get(1), s.get(2));
    ASSERT_LT(ls.p.x, 7.0f);
    second += ls.p.x >= 5.0f;
    EXPECT_EQ(ls.emission.x, ls.p.x >= 5.0f ? 3.0f : 1.0f);
    inv_pdf += 1.0 / ls.pdf_area;
    EXPECT_NEAR(ls.n.z, 1.0f, 1e-6f);
  }
  EXPECT_NEAR(double(second) / n, 6.0 / 7.0, 0.005);  // power 1 vs 2 x 3
  EXPECT_NEAR(inv_pdf / n, 3.0, 0.01);                 // E[1 / pdf] = total area 3
}

// A light far dimmer than its neighbour is chosen with exactly the probability it reports,
// so E[1{chosen} / p] = 1. The choice is monotonic in the random bits: bisection finds the
// measure of the bit patterns that choose each light. With a float CDF searched by a 24-bit u
// a light of relative power 1e-7 was chosen 1.19 times as often as reported, 3e-8 1.79 times.
TEST(LightSampler, ChoiceProbabilityIsExactForDimLights) {
  for (const double ratio : {1e3, 1e7, 3e7, 1e12})
    for (const bool dim_first : {true, false}) {
      Scene scene;
      const Material dim{.emission = Vec3{1.0f}}, bright{.emission = Vec3{float(ratio)}};
      // Equal areas (0.5): the power ratio is the emission ratio.
      testing::add_part(scene, {Triangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}, dim_first ? dim : bright);
      testing::add_part(scene, {Triangle{{5, 0, 0}, {6, 0, 0}, {5, 1, 0}}}, dim_first ? bright : dim);
      const LightSampler lights(scene);
      ASSERT_EQ(lights.distribution().size(), 2u);
      auto second = [&](uint64_t m) { return lights.sample(m << 11, 0.3f, 0.3f).p.x >= 2.0f; };
      uint64_t lo = 0, hi = uint64_t(1) << 53;  // second(lo) is false, second(hi - 1) is true
      ASSERT_FALSE(second(lo));
      ASSERT_TRUE(second(hi - 1));
      while (hi - lo > 1) {
        const uint64_t mid = lo + (hi - lo) / 2;
        (second(mid) ? hi : lo) = mid;
      }
      const double chosen[2] = {std::ldexp(double(hi), -53), 1.0 - std::ldexp(double(hi), -53)};
      for (int k = 0; k < 2; ++k) {
        const LightSample ls = lights.sample(k == 0 ? 0 : ~uint64_t(0), 0.3f, 0.3f);
        EXPECT_EQ(ls.choice_probability, chosen[k]) << ratio << " " << dim_first << " " << k;
        EXPECT_NEAR(ls.pdf_area * 0.5 / chosen[k], 1.0, 1e-6) << ratio << " " << k;
        const bool is_dim = (k == 0) == dim_first;
        const double r = double(float(ratio));  // the emission as stored
        EXPECT_NEAR(ls.choice_probability, (is_dim ? 1.0 : r) / (1.0 + r), 0x1p-52) << ratio << " " << k;
      }
    }
}

// The sampled weight f cos / pdf of a glossy material has the mean of the cosine-sampled
// estimate of the same integral (its directional albedo): a wrong mixture pdf would bias it.
TEST(Bsdf, GlossySamplingWeightsMatchItsValue) {
  const Material m{.type = Material::Type::Glossy, .diffuse = Vec3{0.3f}, .specular = Vec3{0.5f}, .exponent = 20};
  const Vec3 n{0, 0, 1};
  const Vec3 wo = normalize(Vec3{0.5f, 0.2f, 1.0f});
  const int count = 400000;
  double sampled = 0, reference = 0;
  for (int i = 0; i < count; ++i) {
    const PathSampler s(9, uint32_t(i), 0, 0);
    const BsdfSample bs = sample_bsdf(m, n, wo, s.get(0), s.get(1), s.get(2));
    if (bs.valid) sampled += bs.weight.x;
    // reference: uniform hemisphere directions, f cos / (1 / 2 pi)
    const float z = s.get(3), phi = 2 * std::numbers::pi_v<float> * s.get(4), r = std::sqrt(1 - z * z);
    const Vec3 wi{r * std::cos(phi), r * std::sin(phi), z};
    reference += eval_bsdf(m, n, wo, wi).x * z * 2 * std::numbers::pi;
  }
  sampled /= count;
  reference /= count;
  EXPECT_NEAR(sampled, reference, 0.01 * reference);
  EXPECT_LT(sampled, 0.8 + 1e-6);  // energy: kd + ks at most
  // Diffuse: weight is the albedo; mirror: the reflectance along the mirror direction.
  const Material d{.diffuse = Vec3{0.4f}};
  EXPECT_EQ(sample_bsdf(d, n, wo, 0.5f, 0.3f, 0.7f).weight.x, 0.4f);
  const Material mirror{.type = Material::Type::Mirror, .specular = Vec3{0.9f}};
  const BsdfSample ms = sample_bsdf(mirror, n, wo, 0.1f, 0.2f, 0.3f);
  EXPECT_TRUE(ms.specular);
  EXPECT_NEAR(ms.wi.x, -wo.x, 1e-6f);
  EXPECT_NEAR(ms.wi.z, wo.z, 1e-6f);
}

// The normalised Phong lobe ks (e + 2) / (2 pi) cos^e reflects exactly ks at normal incidence
// (its lobe is then entirely above the surface): integral of f cos over the hemisphere,
// by the midpoint rule in (cos theta, phi). With (e + 1) it would reflect ks (e + 1) / (e + 2).
TEST(Bsdf, GlossyLobeAlbedoAtNormalIncidenceIsKs) {
  const Vec3 n{0, 0, 1};
  for (const float e : {0.0f, 1.0f, 10.0f, 100.0f, 1000.0f}) {
    const Material m{.type = Material::Type::Glossy, .diffuse = Vec3{0.2f}, .specular = Vec3{0.7f}, .exponent = e};
    // cos theta = 1 - (1 - t)^4 crowds the nodes at the pole, where a sharp lobe lives.
    const int nt = 4000, nphi = 8;
    double albedo = 0;
    for (int i = 0; i < nt; ++i) {
      const double t = (i + 0.5) / nt, c = 1 - std::pow(1 - t, 4), dc = 4 * std::pow(1 - t, 3) / nt;
      const double s = std::sqrt(1 - c * c);
      for (int j = 0; j < nphi; ++j) {
        const double phi = 2 * std::numbers::pi * (j + 0.5) / nphi;
        const Vec3 wi{float(s * std::cos(phi)), float(s * std::sin(phi)), float(c)};
        albedo += double(eval_bsdf(m, n, n, wi).x) * c * dc * (2 * std::numbers::pi / nphi);
      }
    }
    EXPECT_NEAR(albedo, 0.2 + 0.7, 2e-3) << "exponent " << e;
  }
}

// A very sharp lobe (any exponent >= 0 is valid) stays finite: along the mirror direction
// the cosine can round to 1 + ulp, and (1 + ulp)^1e10 was inf (NaN pixels in manylight).
TEST(Bsdf, SharpGlossyLobeStaysFinite) {
  const Material m{.type = Material::Type::Glossy, .diffuse = Vec3{0.3f}, .specular = Vec3{0.5f}, .exponent = 1e10f};
  const Vec3 n{0, 0, 1};
  int above_one = 0;
  for (int i = 0; i < 2000; ++i) {
    const PathSampler s(3, uint32_t(i), 0, 0);
    const float z = 0.05f + 0.95f * s.get(0), phi = 2 * std::numbers::pi_v<float> * s.get(1);
    const Vec3 wo = normalize(Vec3{std::sqrt(1 - z * z) * std::cos(phi), std::sqrt(1 - z * z) * std::sin(phi), z});
    const Vec3 wi = normalize(Vec3{-wo.x, -wo.y, wo.z});  // the mirror direction
    above_one += dot(reflect(-wo, n), wi) > 1.0f ? 1 : 0;
    const Vec3 f = eval_bsdf(m, n, wo, wi);
    ASSERT_TRUE(std::isfinite(f.x)) << "wo " << wo.x << " " << wo.y << " " << wo.z;
    const BsdfSample bs = sample_bsdf(m, n, wo, 0.1f, s.get(2), s.get(3));
    if (bs.valid) {
      ASSERT_TRUE(std::isfinite(bs.weight.x));
    }
  }
  EXPECT_GT(above_one, 0) << "no direction rounded above 1: the test would not catch the overflow";
}

// The Phong lobe's rim: u1 = 0 samples cos(alpha) = 0, where dot(r, wi) is rounding noise of
// ~1e-8. For exponents near 5 its e-th power is a denormal density, and with no diffuse lobe
// f cos / pdf overflowed: up to 20 % of these samples (1 in 2^24 of a glossy material's) had
// an infinite weight. Every valid sample's weight is finite, for any view.
TEST(Bsdf, GlossyLobeRimSamplesStayFinite) {
  const Vec3 n{0, 0, 1};
  size_t valid = 0;
  for (float e = 4.0f; e <= 7.0f; e += 0.25f) {
    const Material m{.type = Material::Type::Glossy, .diffuse = Vec3{0.0f}, .specular = Vec3{1.0f}, .exponent = e};
    for (int i = 0; i < 200; ++i) {
      const float cos_o = 0.05f + 0.95f * float(i) / 200.0f, phi_o = 0.7f * float(i);
      const float sin_o = std::sqrt(1 - cos_o * cos_o);
      const Vec3 wo = normalize(Vec3{sin_o * std::cos(phi_o), sin_o * std::sin(phi_o), cos_o});
      for (int k = 0; k < 16; ++k) {
        const BsdfSample s = sample_bsdf(m, n, wo, 0.5f, 0.0f, float(k) / 16.0f);
        if (!s.valid) continue;
        ++valid;
        EXPECT_TRUE(std::isfinite(s.weight.x) && std::isfinite(s.weight.y) && std::isfinite(s.weight.z))
            << "e " << e << " wo " << wo.x << " " << wo.y << " " << wo.z << " u2 " << k / 16.0f;
      }
    }
  }
  EXPECT_GT(valid, 0u);  // the rim is sampled, not all dropped
}

// White furnace of the BSDF: a glossy material with kd + ks = 1 reflects at most all the light
// at every incidence (the Phong lobe gives ks at normal incidence and loses what the horizon
// clips off it towards grazing), and at least its diffuse part. The mean sampled weight
// f cos / pdf is the directional albedo; 2e5 samples give it to ~0.3 %.
TEST(Bsdf, GlossyAlbedoStaysWithinKdAndKdPlusKsAtEveryIncidence) {
  const Vec3 n{0, 0, 1};
  const float kd = 0.4f, ks = 0.6f;
  for (const float e : {1.0f, 10.0f, 100.0f})
    for (const float cos_o : {1.0f, 0.7f, 0.3f, 0.05f}) {
      const Material m{.type = Material::Type::Glossy, .diffuse = Vec3{kd}, .specular = Vec3{ks}, .exponent = e};
      const Vec3 wo{std::sqrt(1 - cos_o * cos_o), 0, cos_o};
      const int count = 200000;
      double albedo = 0;
      for (int i = 0; i < count; ++i) {
        const PathSampler s(5, uint32_t(i), 0, 0);
        const BsdfSample bs = sample_bsdf(m, n, wo, s.get(0), s.get(1), s.get(2));
        if (bs.valid) albedo += bs.weight.x;
      }
      albedo /= count;
      EXPECT_LT(albedo, (kd + ks) * 1.01) << "e " << e << ", cos " << cos_o;
      EXPECT_GT(albedo, kd * 0.99) << "e " << e << ", cos " << cos_o;
      if (cos_o == 1.0f) {
        EXPECT_NEAR(albedo, kd + ks, 0.01) << "e " << e;
      }
    }
}

}  // namespace
}  // namespace rayscout

#include "direct_lighting.h"  // src/render (private): the MIS weight of next-event estimation

namespace rayscout {
namespace {

// Veach 1997 eq. 9.13 with beta = 2, as the path integrator's comment says: a sample of density
// f (nf samples) against g (ng samples) weighs (nf f)^2 / ((nf f)^2 + (ng g)^2). The balance
// heuristic (beta = 1) is as unbiased, so no image test saw it replace the power heuristic.
TEST(MisWeight, PowerHeuristicIsVeachsBetaTwo) {
  EXPECT_FLOAT_EQ(detail::power_heuristic(1.0f, 2.0f, 1.0f, 1.0f), 0.8f);   // 4 / (4 + 1)
  EXPECT_FLOAT_EQ(detail::power_heuristic(4.0f, 1.0f, 1.0f, 2.0f), 0.8f);   // 16 / (16 + 4)
  EXPECT_FLOAT_EQ(detail::power_heuristic(1.0f, 1.0f, 1.0f, 3.0f), 0.1f);   // 1 / (1 + 9)
  // The two strategies' weights of one sample add up to 1.
  EXPECT_FLOAT_EQ(detail::power_heuristic(2.0f, 0.7f, 1.0f, 1.9f) + detail::power_heuristic(1.0f, 1.9f, 2.0f, 0.7f), 1.0f);
  EXPECT_EQ(detail::power_heuristic(1.0f, 0.0f, 1.0f, 1.0f), 0.0f);
  EXPECT_EQ(detail::power_heuristic(1.0f, 1.0f, 1.0f, 0.0f), 1.0f);
  EXPECT_EQ(detail::power_heuristic(1.0f, INFINITY, 1.0f, 1.0f), 1.0f);
}

}  // namespace
}  // namespace rayscout
