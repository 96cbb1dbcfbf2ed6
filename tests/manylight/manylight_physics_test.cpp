// The many-light renderer against the path tracer: the same light transport, computed two
// independent ways. manylight_unbiased_test checks the renderer against eq. (1) summed over
// its VPLs; this checks that sum against the path tracer, so an error shared by both sides of
// that test (VPL flux, Russian roulette, shading-point weights) cannot cancel.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "exact_sum.h"
#include "../render/test_scenes.h"
#include "generated_scenes.h"
#include "rayscout/accelerators.h"
#include "rayscout/manylight/channel_mean.h"
#include "rayscout/manylight/shading_points.h"
#include "rayscout/manylight/vpl.h"
#include "rayscout/render/bsdf.h"
#include "rayscout/render/renderer.h"
#include "rayscout/scene/load_scene.h"

namespace rayscout {
namespace {

/// Mean and standard error of the mean of a list of values.
struct MeanSe {
  double mean = 0, se = 0;
};
MeanSe mean_se(const std::vector<double>& v) {
  double sum = 0, sum2 = 0;
  for (double x : v) { sum += x; sum2 += x * x; }
  const double n = double(v.size()), mean = sum / n;
  return {mean, std::sqrt(std::max(0.0, (sum2 / n - mean * mean) / (n - 1.0)))};
}

double image_mean(const std::vector<Vec3>& img) {
  double sum = 0;
  for (const Vec3& p : img) sum += channel_mean(p);
  return sum / double(img.size());
}

// With light paths of at most B surface vertices, the VPLs plus the shading point's gather
// carry light over B + 1 bounces: the path tracer at max_depth = B + 1. Image means over
// several independent VPL sets (exact visibility, no clamping) and several path-tracer seeds.
// B = 5 as well as 0: Russian roulette acts on the vertices after the first bounce. Measured
// (Release): B = 0: 0.0514 +- 0.0002 vs 0.0518 +- 0.0001; B = 5: 0.0825 +- 0.0003 vs 0.0824
// +- 0.0001. Without RR's 1 / survive B = 5 gave 0.0746 (28 SE off).
TEST(ManylightPhysics, VplSumMatchesThePathTracer) {
  // The camera tilted down so the area light is out of view (a handful of pixels straddling
  // its edge made the 2-sample shading points' image mean vary +-10 % between seeds), and the
  // point light 8 cm under the ceiling removed (the ceiling above it, lit at 1 / d^2, made
  // the path tracer's indirect light noisy): the standard errors drop ~20x.
  Scene scene = default_scene();
  scene.camera.look_at = {0.0f, 0.5f, 0.0f};
  scene.point_lights.clear();
  const auto accel = make_accelerator("bvh", scene);
  const bool small = testing::small_scale();
  const int res = 16, vpl_sets = small ? 6 : 12, pt_seeds = 4;
  for (const int bounces : {0, 5}) {
    ManylightConfig c;
    c.width = c.height = res;
    c.spp = 2;  // > 1: the shading points' 1/spp weight matters
    c.vpl_count = small ? 1000 : 2000;
    c.max_vpl_bounces = bounces;
    std::vector<double> ml;
    for (int s = 0; s < vpl_sets; ++s) {
      c.seed = 100 + uint64_t(s);
      const VplSet vpls = generate_vpls(scene, *accel, c);
      const auto points = generate_shading_points(scene, *accel, c);
      ml.push_back(image_mean(testing::exact_sum(scene, *accel, points, vpls.vpls, res, res, 0.0f)));
    }
    std::vector<double> pt;
    RenderConfig rc;
    rc.width = rc.height = res;
    rc.spp = small ? 32 : 128;
    rc.max_depth = bounces + 1;
    for (int s = 0; s < pt_seeds; ++s) {
      rc.seed = 7 + uint64_t(s);
      pt.push_back(image_mean(make_path_integrator()->render(scene, *accel, rc).pixels));
    }
    const MeanSe a = mean_se(ml), b = mean_se(pt);
    const double se = std::hypot(a.se, b.se);
    EXPECT_NEAR(a.mean, b.mean, 4.0 * se) << "bounces " << bounces << ": manylight " << a.mean << " +- " << a.se
                                          << ", path " << b.mean << " +- " << b.se;
  }
}

// The test above leaves the point light out, and the other manylight tests compare the renderer
// with eq. (1) summed by the same tentative_contribution: a point VPL's intensity was checked
// against nothing (halving it passed every manylight test). With the point light as the only
// light and no bounce (B = 0), every VPL is the light itself carrying I / paths, so eq. (1) is
// direct lighting from the point light, which the direct integrator computes without noise:
// the image means differ only by where the pixels are sampled. Camera tilted down as above
// (the ceiling 10 cm over the light made a few pixels dominate the mean). Measured over three
// seeds: within 1.1 %.
TEST(ManylightPhysics, PointLightVplsGiveTheDirectIntegratorsImage) {
  Scene scene = default_scene();
  scene.camera.look_at = {0.0f, 0.5f, 0.0f};
  for (Material& m : scene.materials) m.emission = Vec3(0.0f);
  scene.emissive_triangles.clear();
  ASSERT_EQ(scene.point_lights.size(), 1u);
  const auto accel = make_accelerator("bvh", scene);
  const int res = 16;
  ManylightConfig c;
  c.width = c.height = res;
  c.spp = 16;
  c.vpl_count = 50;
  c.max_vpl_bounces = 0;
  const VplSet vpls = generate_vpls(scene, *accel, c);
  ASSERT_FALSE(vpls.vpls.empty());
  for (const Vpl& v : vpls.vpls) ASSERT_EQ(v.kind, Vpl::Kind::Point);
  const auto points = generate_shading_points(scene, *accel, c);
  const double ml = image_mean(testing::exact_sum(scene, *accel, points, vpls.vpls, res, res, 0.0f));
  RenderConfig rc;
  rc.width = rc.height = res;
  rc.spp = 64;
  const double direct = image_mean(make_direct_integrator()->render(scene, *accel, rc).pixels);
  EXPECT_GT(direct, 0.05);
  EXPECT_NEAR(ml, direct, 0.02 * direct) << "manylight " << ml << ", direct " << direct;
}


// Russian roulette on a light path keeps E[power] of the next VPL at power x E[weight], the
// directional albedo, also where a sample's weight exceeds 1 (a Phong lobe of exponent 1 reflects
// up to (n + 2) / (n + 1) = 1.5 Ks towards the normal): survival min(1, weight) then keeps the
// whole weight. Inside an emitting glossy sphere every light path makes an emitter VPL, then a
// VPL where it first meets the sphere, then (surviving) one at the second hit; the second VPLs'
// summed power matches the first ones' times their albedo (estimated with 256 BSDF samples
// each). Measured: 0.9 % apart (0.3 % at the small scale, standard errors 0.7 % and 0.9 %);
// survival without the min(1, .) loses 8 %.
TEST(ManylightPhysics, LightPathRouletteKeepsTheGlossyAlbedo) {
  Scene scene;
  const Material glossy{.type = Material::Type::Glossy, .diffuse = Vec3{0.1f}, .specular = Vec3{0.85f}, .exponent = 1.0f,
                        .emission = Vec3{1.0f}};
  testing::add_part(scene, testing::inward_sphere({0, 0, 0}, 1.0f, 3), glossy);
  const auto accel = make_accelerator("bvh", scene);
  ManylightConfig c;
  c.vpl_count = testing::small_scale() ? 15000 : 30000;
  c.max_vpl_bounces = 2;
  const VplSet set = generate_vpls(scene, *accel, c);
  // Per batch: k emitter VPLs, the k first hits (no ray leaves the closed sphere), then the
  // second hits of the paths that survived.
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  double predicted = 0, second = 0;
  size_t first_hits = 0, second_hits = 0;
  for (size_t i = 0; i < set.vpls.size();) {
    size_t k = 0;
    for (; i < set.vpls.size() && set.vpls[i].kind == Vpl::Kind::Emitter; ++i) ++k;
    ASSERT_GT(k, 0u);
    for (size_t j = 0; j < k; ++j, ++i) {
      ASSERT_LT(i, set.vpls.size());
      const Vpl& v = set.vpls[i];
      ASSERT_EQ(v.kind, Vpl::Kind::Surface);
      double albedo = 0;
      for (int s = 0; s < 256; ++s) {
        const BsdfSample bs = sample_bsdf(glossy, v.normal, v.wi, u01(rng), u01(rng), u01(rng));
        if (bs.valid) albedo += bs.weight.x / 256.0;
      }
      predicted += v.power.x * albedo;
      ++first_hits;
    }
    for (; i < set.vpls.size() && set.vpls[i].kind == Vpl::Kind::Surface; ++i, ++second_hits) second += set.vpls[i].power.x;
  }
  ASSERT_GT(first_hits, c.vpl_count / 4);
  ASSERT_GT(second_hits, first_hits / 2);
  EXPECT_NEAR(second, predicted, 0.04 * predicted) << first_hits << " first hits, " << second_hits << " second";
}

}  // namespace
}  // namespace rayscout
