// Known answers: radiance in closed spheres and under a square light, ambient occlusion limits.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "rayscout/accelerators.h"
#include "rayscout/render/renderer.h"
#include "rayscout/scene/mesh.h"
#include "test_scenes.h"

namespace rayscout {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

std::string fast_accel() {
  for (const auto& a : accelerators())
    if (a.name == "bvh") return "bvh";
  return "brute";
}

Image render_with(const Integrator& integrator, const Scene& scene, const RenderConfig& cfg) {
  const auto accel = make_accelerator(fast_accel(), scene);
  return integrator.render(scene, *accel, cfg);
}

// A camera inside a sphere of radius r centred at the origin, looking sideways.
Camera inside_camera(float r) {
  Camera cam;
  cam.eye = {0.1f * r, -0.05f * r, 0.07f * r};
  cam.look_at = {1.0f * r, 0.3f * r, -0.2f * r};
  cam.fov_deg = 70;
  return cam;
}

// Point light of intensity I at the centre of a closed diffuse sphere of radius r, albedo rho:
// irradiance on the wall E = I cos / d^2 = I / r^2, radiance L = rho / pi * E = rho I / (pi r^2).
// The tessellated sphere's facets lie inside the sphere (distance h = r cos(phi) <= d <= r,
// cos = h / d), so pixel values lie in [rho I h / (pi r^3) ... rho I / (pi h^2)]: with 5120
// facets phi < 3 degrees, i.e. within 0.3%; we allow 1%.
TEST(Analytic, DirectPointLightInSphere) {
  const float r = 2.0f, rho = 0.6f, intensity = 5.0f;
  Scene scene;
  testing::add_part(scene, testing::sphere({0, 0, 0}, r, 4), Material{.diffuse = Vec3{rho}});
  scene.point_lights.push_back({{0, 0, 0}, Vec3{intensity}});
  scene.camera = inside_camera(r);
  RenderConfig cfg;
  cfg.width = cfg.height = testing::small_scale() ? 8 : 24;
  cfg.spp = 2;
  const Image img = render_with(*make_direct_integrator(), scene, cfg);
  const float expected = rho * intensity / (kPi * r * r);
  for (const Vec3& p : img.pixels) {
    EXPECT_NEAR(p.x, expected, 0.01f * expected);
    EXPECT_EQ(p.x, p.y);
  }
  // The path integrator's first bounce sees the same direct light; no emitters, so its
  // indirect light is rho times the wall's radiance per bounce: L = rho I/(pi r^2) (1 + rho + rho^2).
  cfg.max_depth = 3;
  cfg.spp = 16;
  const Image path = render_with(*make_path_integrator(), scene, cfg);
  const double expected_path = expected * (1 + rho + rho * rho);
  EXPECT_NEAR(testing::mean_channel(path, 1), expected_path, 0.02 * expected_path);
}

// White furnace with emission: a closed sphere of radius 1.5 whose inside emits Le and reflects rho.
// Path tracing with max_depth D sees L = Le (1 + rho + ... + rho^D). Next-event estimation
// inside a sphere is exact (cos cos' / d^2 = 1 / (4 r^2) everywhere), so the noise is small.
struct Furnace {
  float rho = 0.5f, le = 2.0f;
  Scene scene;
  explicit Furnace(float albedo = 0.5f) : rho(albedo) {
    const float r = 1.5f;
    testing::add_part(scene, testing::inward_sphere({0, 0, 0}, r, 3),
                      Material{.diffuse = Vec3{rho}, .emission = Vec3{le}});
    scene.camera = inside_camera(r);
  }
  double radiance(int max_depth) const {
    double sum = 0;
    for (int k = 0; k <= max_depth; ++k) sum += le * std::pow(rho, k);
    return sum;
  }
};

// Inside a sphere the light pdf in solid angle equals the cosine pdf (both d / (2 pi r)), so
// MIS splits every light point 1 : 1 between the strategies with one light sample and
// 9 : 1 with three; weights that did not count the light samples would not sum to 1.
TEST(Analytic, PathFurnaceInEmissiveSphere) {
  const Furnace furnace;
  RenderConfig cfg;
  cfg.width = cfg.height = testing::small_scale() ? 8 : 16;
  cfg.spp = 4;
  for (int light_samples : {1, 3})
    for (int depth : {0, 1, 3}) {
      cfg.max_depth = depth;
      cfg.light_samples = light_samples;
      const Image img = render_with(*make_path_integrator(), furnace.scene, cfg);
      const double expected = furnace.radiance(depth);
      EXPECT_NEAR(testing::mean_channel(img, 0), expected, 0.02 * expected)
          << "max_depth " << depth << ", light samples " << light_samples;
    }
}

// Russian roulette keeps the furnace's expectation and cuts the long paths. With rho = 0.5 and
// rr_depth = 1 the throughput is rho^3 = 0.125 at the first roulette (bounce 2) and 1 after it,
// so a path goes on with probability 0.125, then 0.5 at every vertex: the path rays of depth 12
// fall from 11 per sample to 1 + 1 + 0.125 (1 + 0.5 + ... + 0.5^8), about 2.25.
TEST(Analytic, RussianRouletteKeepsTheFurnaceRadiance) {
  const Furnace furnace;
  const Scene& scene = furnace.scene;
  RenderConfig cfg;
  cfg.width = cfg.height = testing::small_scale() ? 8 : 16;
  cfg.spp = 64;
  cfg.max_depth = 12;
  const double expected = furnace.radiance(cfg.max_depth);
  auto path_rays = [](const RenderStats& stats) {
    uint64_t n = 0;
    for (const BatchStats& b : stats.batches) n += b.info.kind == "path" ? b.rays : 0;
    return n;
  };
  const auto accel = make_accelerator(fast_accel(), scene);
  const auto path = make_path_integrator();
  RenderStats off_stats, on_stats;
  cfg.rr_depth = cfg.max_depth;
  const Image off = path->render(scene, *accel, cfg, &off_stats);
  cfg.rr_depth = 1;
  const Image on = path->render(scene, *accel, cfg, &on_stats);
  const double paths = double(cfg.width * cfg.height * cfg.spp);
  // Without: bounces 0..10 each send a path ray (the 12th vertex only adds emission), but for a
  // few of ~1e-3 whose sampled direction is invalid.
  EXPECT_LE(double(path_rays(off_stats)), 11 * paths);
  EXPECT_GT(double(path_rays(off_stats)), 10.99 * paths);
  EXPECT_LT(double(path_rays(on_stats)), 2.35 * paths);
  EXPECT_GT(double(path_rays(on_stats)), 2.15 * paths);
  EXPECT_NEAR(testing::mean_channel(off, 0), expected, 0.01 * expected);
  // The roulette's noise: a path's tail beyond bounce 2 (expected Le rho^3 / (1 - rho) = Le / 4)
  // is ~2 Le with probability 0.125, a standard deviation of ~0.66 Le; over >= 4096 paths
  // that is 0.5 % of the expected ~2 Le.
  EXPECT_NEAR(testing::mean_channel(on, 0), expected, 0.02 * expected);
  EXPECT_NE(testing::mean_channel(on, 0), testing::mean_channel(off, 0));  // the roulette did play
}

// The roulette's survival probability has a floor of 0.05 (kMinSurvival), which bounds the
// 1 / p weight. With rho = 0.02 the throughput at every roulette is below it (rho^3 = 8e-6 at
// bounce 2, 8e-6 / 0.05 rho = 3.2e-6 after a survival), so a path goes on with probability
// exactly 0.05 each time: 2 + 0.05 / 0.95 = 2.053 path rays a sample. Without the floor it
// would be 2 + 8e-6; the radiance Le (1 + rho + rho^2 + ...) is the same either way.
TEST(Analytic, RussianRouletteSurvivalHasAFloorOfFivePercent) {
  const Furnace furnace(0.02f);
  RenderConfig cfg;
  cfg.width = cfg.height = testing::small_scale() ? 8 : 16;
  cfg.spp = 64;
  cfg.max_depth = 12;
  cfg.rr_depth = 1;
  RenderStats stats;
  const auto accel = make_accelerator(fast_accel(), furnace.scene);
  const Image img = make_path_integrator()->render(furnace.scene, *accel, cfg, &stats);
  uint64_t path_rays = 0;
  for (const BatchStats& b : stats.batches) path_rays += b.info.kind == "path" ? b.rays : 0;
  const double paths = double(cfg.width * cfg.height * cfg.spp);
  // 4096 paths at the small scale: the 0.05 coin's count has a standard deviation of 0.0034 a path.
  EXPECT_GT(double(path_rays), 2.03 * paths);
  EXPECT_LT(double(path_rays), 2.08 * paths);
  const double expected = furnace.radiance(cfg.max_depth);
  EXPECT_NEAR(testing::mean_channel(img, 0), expected, 0.01 * expected);
}

// A closed box whose walls emit Le and reflect with albedo <= 1 holds radiance <= Le (D + 1)
// after D bounces. CornellBox-Glossy's sphere material as its MTL gives it (Kd up to 0.663,
// Ks 0.9, Ns 400) reflects up to ~1.5 and gave 313410 at D = 48; scaled by the MTL reader's
// energy conservation it stays below the bound.
TEST(Analytic, GlossyFurnaceOfAnMtlMaterialStaysBounded) {
  const float le = 1.0f;
  const int depth = 48;
  Material m = material_from_mtl("sphere", {0.486f, 0.631f, 0.663f}, Vec3(0.9f), 400.0f, 2, Vec3(le));
  Scene scene;
  Material raw = m;
  conserve_energy(m);
  testing::add_part(scene, testing::inward_box({-1, -1, -1}, {1, 1, 1}), m);
  scene.camera = inside_camera(1.0f);
  RenderConfig cfg;
  cfg.width = cfg.height = 8;
  cfg.spp = 4;
  cfg.max_depth = depth;
  const Image img = render_with(*make_path_integrator(), scene, cfg);
  for (const Vec3& p : img.pixels) EXPECT_LE(max_component(p), le * (depth + 1));
  EXPECT_GT(testing::mean_channel(img, 2), 3 * le);  // it does reflect: far above Le alone (measured 4.67)
  scene.materials[0] = raw;  // the test's counter-check: the unscaled material breaks the bound
  EXPECT_GT(testing::mean_channel(render_with(*make_path_integrator(), scene, cfg), 2), le * (depth + 1));
}

// Irradiance of a square light (side a, radiance Le, facing down) at height h above the
// point under its centre: E = pi Le F with the form factor of four a/2 x a/2 rectangles,
// each seen from under a corner (Howell's catalogue, config. B-3):
// F = 1/(2 pi) (A/sqrt(1+A^2) atan(B/sqrt(1+A^2)) + B/sqrt(1+B^2) atan(A/sqrt(1+B^2))), A = B = a/(2h).
// A diffuse floor of albedo rho has L = rho / pi E = rho Le 4 F there. Tolerance 3% (the
// estimate of 16 spp x 64 light samples per pixel is accurate to ~0.5%; the pixels see a
// region of radius ~0.02 h around the centre, where E falls by less than 0.1%).
TEST(Analytic, AreaLightIrradianceOnPlane) {
  const float a = 1.0f, h = 1.0f, le = 4.0f, rho = 0.7f;
  Scene scene;
  testing::add_part(scene, testing::quad({-20, -20, 0}, {40, 0, 0}, {0, 40, 0}), Material{.diffuse = Vec3{rho}});
  testing::add_part(scene, testing::quad({-a / 2, -a / 2, h}, {0, a, 0}, {a, 0, 0}),  // normal -z
                    Material{.diffuse = Vec3{0.0f}, .emission = Vec3{le}});
  scene.camera.eye = {0, -3, 2};
  scene.camera.look_at = {0, 0, 0};
  scene.camera.up = {0, 0, 1};
  scene.camera.fov_deg = 1.0f;
  RenderConfig cfg;
  cfg.width = cfg.height = 4;
  cfg.spp = testing::small_scale() ? 4 : 16;
  cfg.light_samples = 64;
  const Image img = render_with(*make_area_integrator(), scene, cfg);
  const double A = a / (2 * h), s = std::sqrt(1 + A * A);
  const double f_corner = (1 / (2 * std::numbers::pi)) * 2 * (A / s) * std::atan(A / s);
  const double expected = rho * le * 4 * f_corner;
  EXPECT_NEAR(testing::mean_channel(img, 0), expected, 0.03 * expected);
  // Direct ignores area lights: the floor is black.
  EXPECT_EQ(testing::mean_channel(render_with(*make_direct_integrator(), scene, cfg), 0), 0.0);
}

// A glossy floor reflecting a small area light: direct light only, since the light is black
// and nothing else is there. `path` at max_depth 2 combines next-event estimation with the
// BSDF-sampled bounce by MIS; `area` uses next-event estimation alone. Same expectation;
// on the highlight the sharp lobe makes light sampling noisy, which MIS removes.
TEST(Analytic, PathMisKeepsTheDirectLightAndCutsItsNoise) {
  Scene scene;
  Material floor{.type = Material::Type::Glossy, .diffuse = Vec3{0.1f}, .specular = Vec3{0.8f}, .exponent = 1000};
  testing::add_part(scene, testing::quad({-2, -4, 0}, {4, 0, 0}, {0, 8, 0}), floor);
  const float side = 1.5f;  // facing -y, centred where the camera sees its mirror image
  testing::add_part(scene, testing::quad({-side / 2, 3, 1 - side / 2}, {side, 0, 0}, {0, 0, side}),
                    Material{.diffuse = Vec3{0.0f}, .emission = Vec3{10.0f}});
  scene.camera.eye = {0, -3, 1};
  scene.camera.look_at = {0, 0, 0};
  scene.camera.up = {0, 0, 1};
  scene.camera.fov_deg = 30;
  RenderConfig cfg;
  cfg.width = cfg.height = testing::small_scale() ? 12 : 24;
  cfg.spp = 1;
  cfg.light_samples = 2;  // the weights must count them (power heuristic of 2 against 1)
  cfg.max_depth = 2;
  const auto accel = make_accelerator(fast_accel(), scene);
  const int renders = testing::small_scale() ? 16 : 32;
  struct Moments {
    std::vector<double> sum, sum2;  // per pixel over the renders
    std::vector<double> means;      // image mean of each render
  };
  auto moments = [&](const Integrator& integrator) {
    Moments m;
    m.sum.assign(size_t(cfg.width * cfg.height), 0.0);
    m.sum2 = m.sum;
    for (int r = 0; r < renders; ++r) {
      cfg.seed = uint64_t(100 + r);
      const Image img = integrator.render(scene, *accel, cfg);
      for (size_t i = 0; i < img.pixels.size(); ++i) {
        m.sum[i] += img.pixels[i].y;
        m.sum2[i] += double(img.pixels[i].y) * img.pixels[i].y;
      }
      m.means.push_back(testing::mean_channel(img, 1));
    }
    return m;
  };
  const Moments mis = moments(*make_path_integrator()), nee = moments(*make_area_integrator());
  auto mean_and_se = [&](const std::vector<double>& x) {
    double s = 0, s2 = 0;
    for (double v : x) s += v, s2 += v * v;
    const double mean = s / double(x.size());
    return std::pair{mean, std::sqrt((s2 / double(x.size()) - mean * mean) / double(x.size() - 1))};
  };
  auto pixel_variance = [&](const Moments& m) {  // summed over the pixels
    double v = 0;
    for (size_t i = 0; i < m.sum.size(); ++i) v += m.sum2[i] / renders - (m.sum[i] / renders) * (m.sum[i] / renders);
    return v;
  };
  const auto [mean_mis, se_mis] = mean_and_se(mis.means);
  const auto [mean_nee, se_nee] = mean_and_se(nee.means);
  EXPECT_GT(mean_nee, 0.05);  // the highlight is in the picture
  EXPECT_NEAR(mean_mis, mean_nee, 4 * std::hypot(se_mis, se_nee)) << "SE " << se_mis << ", " << se_nee;
  EXPECT_LT(pixel_variance(mis), pixel_variance(nee) / 4) << pixel_variance(mis) << " vs " << pixel_variance(nee);
}

TEST(Analytic, AmbientOcclusionOpenPlaneIsOne) {
  Scene scene;
  testing::add_part(scene, testing::grid(8), Material{});
  scene.camera.eye = {0.5f, 0.5f, 1.0f};
  scene.camera.look_at = {0.5f, 0.5f, 0.0f};
  scene.camera.fov_deg = 40;
  RenderConfig cfg;
  cfg.width = cfg.height = 16;
  cfg.ao_samples = 8;
  cfg.ao_radius = 5.0f;
  const Image img = render_with(*make_ao_integrator(), scene, cfg);
  for (const Vec3& p : img.pixels) EXPECT_FLOAT_EQ(p.x, 1.0f);
}

TEST(Analytic, AmbientOcclusionClosedBoxIsZero) {
  Scene scene;
  testing::add_part(scene, testing::inward_box({-1, -1, -1}, {1, 1, 1}), Material{});
  scene.camera.eye = {0.2f, 0.1f, 0.3f};
  scene.camera.look_at = {1, 0.5f, -0.5f};
  RenderConfig cfg;
  cfg.width = cfg.height = 16;
  cfg.ao_samples = 8;
  cfg.ao_radius = 10.0f;
  const Image img = render_with(*make_ao_integrator(), scene, cfg);
  for (const Vec3& p : img.pixels) EXPECT_EQ(p.x, 0.0f);
  // With a radius far below the box size the rays are free again except near edges.
  cfg.ao_radius = 1e-3f;
  const Image open = render_with(*make_ao_integrator(), scene, cfg);
  EXPECT_GT(testing::mean_channel(open, 0), 0.95);
}

// Rays leave a surface from an origin pushed off it, not by skipping the first stretch of the
// ray: a skip as long as the offset also skips a wall that close, so corners leaked. Far from
// the origin the offset (1e-5 of the largest coordinate) is 0.5 % of this 2-unit box, and a
// tmin skip let 2 % of the AO pixels of a closed box see out and 11 % of the pixels of a
// mirror box lose light (1.6 % and 7.2 % in this view). Spawned rays leave none here, and on
// other views only pixels whose hit point rounds past the corner (0.03 % and 0.1 %).
TEST(Analytic, ClosedBoxesFarFromTheOriginDoNotLeakAtTheirCorners) {
  const Vec3 far{1000, 1000, 1000};
  Camera cam;
  cam.eye = far;
  cam.look_at = far + Vec3{0.3f, 0.2f, -1.0f};
  cam.fov_deg = 90;
  RenderConfig cfg;
  cfg.width = cfg.height = 64;
  cfg.spp = 2;
  auto leaking_share = [&](const Image& img, float expected) {
    size_t wrong = 0;
    for (const Vec3& p : img.pixels) wrong += std::fabs(p.x - expected) > 1e-4f * (1 + expected);
    return double(wrong) / double(img.pixels.size());
  };
  Scene ao_box;
  testing::add_part(ao_box, testing::inward_box(far - Vec3{1}, far + Vec3{1}), Material{});
  ao_box.camera = cam;
  cfg.ao_samples = 8;
  cfg.ao_radius = 100.0f;
  EXPECT_LT(leaking_share(render_with(*make_ao_integrator(), ao_box, cfg), 0.0f), 0.005);
  // Mirror walls of reflectance 1/2 that emit 1: 10 bounces see 2 - 2^-10 everywhere.
  Scene mirror_box;
  testing::add_part(mirror_box, testing::inward_box(far - Vec3{1}, far + Vec3{1}),
                    Material{.type = Material::Type::Mirror, .specular = Vec3{0.5f}, .emission = Vec3{1.0f}});
  mirror_box.camera = cam;
  cfg.max_depth = 10;
  EXPECT_LT(leaking_share(render_with(*make_direct_integrator(), mirror_box, cfg), 2.0f - 1.0f / 1024), 0.01);
}

// Between two parallel planes h apart, a cosine-distributed ray of length R escapes when
// cos(theta) < h / R; sin^2(theta) is uniform for cosine rays, so AO = (h / R)^2 (uniform
// hemisphere rays would give h / R: 0.5 and 0.25 instead of 0.25 and 0.0625).
TEST(Analytic, AmbientOcclusionBetweenParallelPlanes) {
  const float h = 1.0f;
  Scene scene;
  testing::add_part(scene, testing::quad({-50, -50, 0}, {100, 0, 0}, {0, 100, 0}), Material{});
  testing::add_part(scene, testing::quad({-50, -50, h}, {0, 100, 0}, {100, 0, 0}), Material{});  // normal -z
  scene.camera.eye = {0, 0, 0.5f * h};
  scene.camera.look_at = {0, 0, 0};
  scene.camera.fov_deg = 30;
  RenderConfig cfg;
  cfg.width = cfg.height = 16;
  cfg.spp = testing::small_scale() ? 1 : 4;
  cfg.ao_samples = 64;
  for (const float radius : {2.0f, 4.0f}) {
    cfg.ao_radius = radius;
    const double expected = double(h / radius) * (h / radius);
    const double rays = double(cfg.width) * cfg.height * cfg.spp * cfg.ao_samples;
    const double se = std::sqrt(expected * (1 - expected) / rays);
    EXPECT_NEAR(testing::mean_channel(render_with(*make_ao_integrator(), scene, cfg), 0), expected, 4 * se) << "R " << radius;
  }
}

// A point light of intensity I at height h over a diffuse floor of albedo rho: at horizontal
// distance x the floor shows L = rho / pi * I cos / d^2 = rho I h / (pi d^3), d^2 = h^2 + x^2.
// The other point-light tests see the light at normal incidence (cos = 1); here cos falls to
// 1/2 (x = 1.73). A narrow view of each point (radius ~0.003) keeps L within 0.1 %.
TEST(Analytic, PointLightFollowsLambertsCosineLaw) {
  const float rho = 0.5f, intensity = 3.0f, h = 1.0f;
  Scene scene;
  testing::add_part(scene, testing::quad({-10, -10, 0}, {20, 0, 0}, {0, 20, 0}), Material{.diffuse = Vec3{rho}});
  scene.point_lights.push_back({{0, 0, h}, Vec3{intensity}});
  RenderConfig cfg;
  cfg.width = cfg.height = 2;
  cfg.spp = 1;
  for (const float x : {0.0f, 1.0f, 1.7320508f}) {
    scene.camera.eye = {x, -3, 2};
    scene.camera.look_at = {x, 0, 0};
    scene.camera.up = {0, 0, 1};
    scene.camera.fov_deg = 0.1f;
    const double d = std::sqrt(double(h) * h + double(x) * x);
    const double expected = rho * intensity * h / (std::numbers::pi * d * d * d);
    EXPECT_NEAR(testing::mean_channel(render_with(*make_direct_integrator(), scene, cfg), 0), expected, 0.002 * expected)
        << "x = " << x;
  }
}

// A perfect mirror (reflectance 1) shows the lit floor it faces with the floor's radiance.
TEST(Analytic, MirrorReflectsRadianceUnchanged) {
  Scene scene;
  const float rho = 0.5f;
  testing::add_part(scene, testing::quad({-10, -10, 0}, {20, 0, 0}, {0, 20, 0}), Material{.diffuse = Vec3{rho}});
  testing::add_part(scene, testing::quad({-10, -10, 4}, {0, 20, 0}, {20, 0, 0}),  // ceiling mirror, normal -z
                    Material{.type = Material::Type::Mirror, .specular = Vec3{1.0f}});
  scene.point_lights.push_back({{0, 0, 1}, Vec3{3.0f}});
  scene.camera.eye = {0, 0, 2};
  scene.camera.look_at = {0, 0, 5};  // looking up into the mirror, the floor beneath seen in it
  scene.camera.up = {0, 1, 0};
  scene.camera.fov_deg = 0.1f;  // sees the floor within 0.005 of (0, 0, 0): cos^3 falloff < 1e-4
  RenderConfig cfg;
  cfg.width = cfg.height = 2;
  cfg.spp = 1;
  const Image img = render_with(*make_direct_integrator(), scene, cfg);
  const float expected = rho / kPi * 3.0f / 1.0f;  // point light 1 above the floor point (0, 0, 0)
  EXPECT_NEAR(testing::mean_channel(img, 0), expected, 0.002 * expected);
  cfg.max_depth = 0;  // no reflection rays: black
  EXPECT_EQ(testing::mean_channel(render_with(*make_direct_integrator(), scene, cfg), 0), 0.0);
}

// Surfaces reflect on both sides but light never passes through them, and emitters emit on the
// side of their normal only. A floor (normal +z) with a point light and an area light under
// it (facing up at it) is black from above for every integrator, lit from below; the area
// light is black seen from behind and shows Le in front.
TEST(Analytic, LightStaysOnItsSideOfASurface) {
  const float rho = 0.5f, intensity = 3.0f, le = 5.0f;
  Scene scene;
  testing::add_part(scene, testing::quad({-10, -10, 0}, {20, 0, 0}, {0, 20, 0}), Material{.diffuse = Vec3{rho}});
  testing::add_part(scene, testing::quad({2, 2, -0.5f}, {1, 0, 0}, {0, 1, 0}),  // normal +z: emits up
                    Material{.diffuse = Vec3{0.0f}, .emission = Vec3{le}});
  scene.point_lights.push_back({{0, 0, -1}, Vec3{intensity}});
  scene.camera.up = {0, 1, 0};
  scene.camera.fov_deg = 0.1f;
  RenderConfig cfg;
  cfg.width = cfg.height = 2;
  cfg.spp = 4;
  cfg.max_depth = 3;
  cfg.light_samples = 4;
  auto mean = [&](const Integrator& integrator) {
    return testing::mean_channel(render_with(integrator, scene, cfg), 0);
  };
  scene.camera.eye = {0, 0, 2};  // above the floor, looking down at the point over the light
  scene.camera.look_at = {0, 0, 0};
  for (const auto& integrator : {make_direct_integrator(), make_area_integrator(), make_path_integrator()})
    EXPECT_EQ(mean(*integrator), 0.0) << integrator->name();
  scene.camera.eye = {0, 0, -0.2f};  // under the floor, looking up at the same point
  const double lit = rho / std::numbers::pi * intensity;  // E = I / 1^2 from the point light
  EXPECT_NEAR(mean(*make_direct_integrator()), lit, 0.002 * lit);
  EXPECT_GT(mean(*make_area_integrator()), lit);  // the area light adds to it
  scene.camera.eye = {2.5f, 2.5f, 2.0f};  // above the floor right over the area light: unlit
  scene.camera.look_at = {2.5f, 2.5f, 0.0f};
  EXPECT_EQ(mean(*make_area_integrator()), 0.0);
  scene.camera.eye = {2.5f, 2.5f, -2.0f};  // under the light, looking up at its back
  scene.camera.look_at = {2.5f, 2.5f, 0.0f};
  EXPECT_EQ(mean(*make_path_integrator()), 0.0);
  scene.camera.eye = {2.5f, 2.5f, -0.1f};  // between floor and light, looking down at its front
  scene.camera.look_at = {2.5f, 2.5f, -1.0f};
  EXPECT_EQ(mean(*make_direct_integrator()), le);
}

// Mirror walls of reflectance rho that emit Le: every path is one chain of mirror bounces and
// sees Le (1 + rho + ... + rho^D) after D of them, with no noise, in the path integrator as in
// direct (emission after a mirror bounce counts in full; there is no light to sample).
TEST(Analytic, PathFurnaceOfEmissiveMirrors) {
  const float rho = 0.5f, le = 1.0f;
  Scene scene;
  testing::add_part(scene, testing::inward_box({-1, -1, -1}, {1, 1, 1}),
                    Material{.type = Material::Type::Mirror, .specular = Vec3{rho}, .emission = Vec3{le}});
  scene.camera = inside_camera(1.0f);
  RenderConfig cfg;
  cfg.width = cfg.height = 8;
  cfg.spp = 2;
  for (int depth : {0, 1, 6}) {
    cfg.max_depth = cfg.rr_depth = depth;
    double expected = 0;
    for (int k = 0; k <= depth; ++k) expected += le * std::pow(rho, k);
    for (const auto& integrator : {make_direct_integrator(), make_path_integrator()}) {
      const Image img = render_with(*integrator, scene, cfg);
      size_t off = 0;
      for (const Vec3& p : img.pixels) off += std::fabs(p.x - expected) > 1e-5 * expected;
      EXPECT_LE(off, img.pixels.size() / 50) << integrator->name() << " max_depth " << depth;  // corner pixels
      EXPECT_NEAR(testing::mean_channel(img, 0), expected, 0.01 * expected) << integrator->name();
    }
  }
}

}  // namespace
}  // namespace rayscout
