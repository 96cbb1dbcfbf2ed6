// Clustering, VPL generation and the sampling distributions of VisibilityCluster.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

#include "rayscout/accelerators.h"
#include "rayscout/core/input_error.h"
#include "rayscout/manylight/channel_mean.h"
#include "rayscout/manylight/manylight_renderer.h"
#include "rayscout/manylight/shading_points.h"
#include "rayscout/manylight/visibility_cluster.h"
#include "rayscout/manylight/vpl.h"
#include "rayscout/scene/load_scene.h"

namespace rayscout {
namespace {

TEST(ManylightClustering, EveryItemExactlyOnceInBalancedClusters) {
  std::vector<Vec3> pos, nrm;
  for (int i = 0; i < 1000; ++i) {
    pos.push_back(Vec3(float(i % 10), float((i / 10) % 10), float(i / 100)));
    nrm.push_back(Vec3(0, i % 2 ? 1.0f : -1.0f, 0));
  }
  const Clustering c = cluster_points(pos, nrm, 10.0f, 1.0f, 30);  // rounds up to 32
  ASSERT_EQ(c.size(), 32u);
  std::vector<uint32_t> sorted = c.order;
  std::sort(sorted.begin(), sorted.end());
  for (uint32_t i = 0; i < 1000; ++i) ASSERT_EQ(sorted[i], i);
  for (size_t k = 0; k < c.size(); ++k) {
    EXPECT_GE(c.count(k), 31u);
    EXPECT_LE(c.count(k), 32u);
  }
}

TEST(ManylightClustering, MoreClustersThanPointsGiveOnePointEach) {
  // Up to the largest int: 2^31 - 1 once made ceil_log2 shift past 31 bits and never end.
  std::vector<Vec3> pos, nrm;
  for (int i = 0; i < 5; ++i) {
    pos.push_back(Vec3(float(i), 0, 0));
    nrm.push_back(Vec3(0, 1, 0));
  }
  for (const int clusters : {8, (1 << 30) + 1, std::numeric_limits<int>::max()}) {
    const Clustering c = cluster_points(pos, nrm, 5.0f, 1.0f, clusters);
    ASSERT_EQ(c.size(), 5u) << clusters;
    for (size_t k = 0; k < c.size(); ++k) EXPECT_EQ(c.count(k), 1u) << clusters;
  }
}

TEST(ManylightClustering, NormalsSeparateCoincidentPoints) {
  // Two coincident sheets facing opposite ways must never share a cluster.
  std::vector<Vec3> pos, nrm;
  for (int i = 0; i < 256; ++i) {
    pos.push_back(Vec3(float(i % 16) * 0.01f, 0, float(i / 16) * 0.01f));
    nrm.push_back(Vec3(0, 1, 0));
    pos.push_back(pos.back());
    nrm.push_back(Vec3(0, -1, 0));
  }
  const Clustering c = cluster_points(pos, nrm, 1.0f, 1.0f, 8);
  ASSERT_EQ(c.size(), 8u);
  size_t shared = 0;  // clusters of more than one point: the check below is not vacuous
  for (size_t k = 0; k < c.size(); ++k) shared += c.count(k) > 1;
  EXPECT_EQ(shared, 8u);
  for (size_t k = 0; k < c.size(); ++k) {
    const float y0 = nrm[c.order[c.begin[k]]].y;
    for (uint32_t j = c.begin[k]; j < c.begin[k + 1]; ++j) EXPECT_EQ(nrm[c.order[j]].y, y0);
  }
}

TEST(ManylightVpls, PowerIsConservedAndPathsAreCounted) {
  const Scene scene = default_scene();
  auto accel = make_accelerator("brute", scene);
  ManylightConfig config;
  config.vpl_count = 2000;
  const VplSet set = generate_vpls(scene, *accel, config);
  ASSERT_GE(set.vpls.size(), 2000u);
  ASSERT_GT(set.light_paths, 0u);
  // The path starts carry the lights' total power (point: 4 pi I; one-sided area: pi Le A).
  double expected = 0, got = 0;
  for (const auto& pl : scene.point_lights) expected += 4 * std::numbers::pi_v<float> * channel_mean(pl.intensity);
  for (uint32_t id : scene.emissive_triangles)
    expected += std::numbers::pi_v<float> * channel_mean(scene.material_of(id).emission) * scene.triangles[id].area();
  for (const auto& v : set.vpls) {
    if (v.kind == Vpl::Kind::Point) got += 4 * std::numbers::pi_v<float> * channel_mean(v.power);
    if (v.kind == Vpl::Kind::Emitter) got += channel_mean(v.power);
  }
  EXPECT_NEAR(got, expected, 1e-3 * expected);
  size_t surface = std::count_if(set.vpls.begin(), set.vpls.end(), [](const Vpl& v) { return v.kind == Vpl::Kind::Surface; });
  EXPECT_GT(surface, set.vpls.size() / 2) << "most VPLs are indirect-light vertices";
}

// "At least N, a few more": whole light paths are kept, but a small N is not rounded up to a
// batch of hundreds of paths (--vpls 20 used to make 680 VPLs).
TEST(ManylightVpls, CountIsAtLeastTheTargetAndCloseToIt) {
  const Scene scene = default_scene();
  auto accel = make_accelerator("bvh", scene);
  ManylightConfig config;
  for (size_t n : {1u, 10u, 20u, 100u, 1000u, 5000u}) {
    config.vpl_count = n;
    const VplSet set = generate_vpls(scene, *accel, config);
    EXPECT_GE(set.vpls.size(), n);
    EXPECT_LE(set.vpls.size(), n + std::max<size_t>(12, n / 8)) << "--vpls " << n;
  }
}

// t = I f G of eq. (1), G = cos_x / max(d^2, clamp^2), worked out by hand for each VPL kind at a
// point of a diffuse floor (albedo 0.5, f = 0.5 / pi) facing +y. The unbiasedness tests sum
// the same function on both sides, so only values like these check it.
TEST(ManylightVpls, TentativeContributionByHand) {
  Scene scene;
  scene.materials.push_back(Material{.diffuse = Vec3(0.5f)});
  ShadingPoint sp;
  sp.position = Vec3(0.0f);
  sp.normal = Vec3(0, 1, 0);
  sp.wo = Vec3(0, 1, 0);
  sp.weight = Vec3(1.0f);
  const double f = 0.5 / std::numbers::pi;
  auto t = [&](const Vpl& v, float clamp = 0.0f) { return double(tentative_contribution(scene, sp, v, clamp).x); };
  // A point VPL of intensity 2 at (0, 2, 0): cos 1, d^2 4; at (2, 2, 0): cos 1/sqrt(2), d^2 8.
  Vpl point{.position = {0, 2, 0}, .normal = {}, .wi = {}, .power = Vec3(2.0f), .kind = Vpl::Kind::Point};
  EXPECT_NEAR(t(point), 2 * f / 4, 1e-7);
  point.position = {2, 2, 0};
  EXPECT_NEAR(t(point), 2 * f * std::sqrt(0.5) / 8, 1e-7);
  // Clamped: d^2 = 8 below clamp^2 = 9 counts as 9; above it, unchanged.
  EXPECT_NEAR(t(point, 3.0f), 2 * f * std::sqrt(0.5) / 9, 1e-7);
  EXPECT_NEAR(t(point, 2.0f), 2 * f * std::sqrt(0.5) / 8, 1e-7);
  // Behind the shading point's surface: nothing.
  point.position = {0, -2, 0};
  EXPECT_EQ(t(point), 0.0);
  // An emitter point facing down at (0, 2, 0) with power 3: intensity 3 cos_l / pi towards sp
  // (cos_l 1 straight below, 1/sqrt(2) from (2, 2, 0)), none when it faces up.
  Vpl emitter{.position = {0, 2, 0}, .normal = {0, -1, 0}, .wi = {}, .power = Vec3(3.0f),
              .kind = Vpl::Kind::Emitter};
  EXPECT_NEAR(t(emitter), 3 / std::numbers::pi * f / 4, 1e-7);
  emitter.position = {2, 2, 0};
  EXPECT_NEAR(t(emitter), 3 / std::numbers::pi * std::sqrt(0.5) * f * std::sqrt(0.5) / 8, 1e-7);
  emitter.normal = {0, 1, 0};
  EXPECT_EQ(t(emitter), 0.0);
  // A surface vertex on a ceiling (normal -y, the same diffuse material) lit with flux 4:
  // intensity 4 f cos_l towards sp, whatever direction it was lit from (wi).
  Vpl surface{.position = {0, 2, 0}, .normal = {0, -1, 0}, .wi = normalize(Vec3(1, -1, 0)), .power = Vec3(4.0f),
              .material = 0, .kind = Vpl::Kind::Surface};
  EXPECT_NEAR(t(surface), 4 * f * 1 * f / 4, 1e-7);
}

// A dark point light carries no power: it is never chosen. Alone, it used to divide the
// light cdf by 0 and make every VPL NaN (an all-NaN image with exit 0).
TEST(ManylightVpls, DarkPointLightsAreNeverChosen) {
  Scene scene = default_scene();
  scene.point_lights.push_back({scene.bounds().center(), Vec3(0.0f)});
  auto accel = make_accelerator("bvh", scene);
  ManylightConfig config;
  config.vpl_count = 500;
  const VplSet set = generate_vpls(scene, *accel, config);
  ASSERT_GE(set.vpls.size(), 500u);
  for (const Vpl& v : set.vpls) {
    ASSERT_TRUE(is_finite(v.power));
    if (v.kind == Vpl::Kind::Point) {
      EXPECT_GT(channel_mean(v.power), 0.0f);
    }
  }
  scene.emissive_triangles.clear();
  scene.point_lights.assign(1, {scene.bounds().center(), Vec3(0.0f)});
  EXPECT_TRUE(generate_vpls(scene, *accel, config).vpls.empty());
}

// A light whose power (4 pi I, or pi Le A) overflows float, or lights whose powers together
// do, is an input error naming it; it used to end in an internal error of the light cdf
// (exit 1). The brightest light that fits still gives finite VPLs.
TEST(ManylightVpls, PowerBeyondTheFloatRangeIsAnInputError) {
  Scene scene = default_scene();
  scene.emissive_triangles.clear();
  const Vec3 at = scene.bounds().center();
  auto accel = make_accelerator("bvh", scene);
  ManylightConfig config;
  config.vpl_count = 100;
  const auto error_of = [&] {
    try {
      generate_vpls(scene, *accel, config);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  scene.point_lights = {{at, Vec3(1e37f)}};  // 4 pi 1e37 = 1.3e38 < 3.4e38
  EXPECT_EQ(error_of(), "");
  for (const Vpl& v : generate_vpls(scene, *accel, config).vpls) ASSERT_TRUE(is_finite(v.power));
  scene.point_lights = {{at, Vec3(1e37f)}, {at, Vec3(1.0f)}, {at, Vec3(3e37f)}};
  EXPECT_EQ(error_of(), "manylight: the power of point light 2 overflows float (its intensity is too large)");
  scene.point_lights = {{at, Vec3(1e37f)}, {at, Vec3(1e37f)}, {at, Vec3(1e37f)}};
  EXPECT_EQ(error_of(), "manylight: the lights' total power overflows float (intensities or emissions too large)");
}

// The Cornell box's clustering at a small size: 32x24 shading points, 500 VPLs, 16 x 16 clusters.
ManylightConfig small_clustered_config() {
  ManylightConfig config;
  config.width = 32;
  config.height = 24;
  config.vpl_count = 500;
  config.shading_clusters = config.vpl_clusters = 16;
  return config;
}

TEST(ManylightVisibilityClusters, PmfsArePositiveAndNormalised) {
  const Scene scene = default_scene();
  auto accel = make_accelerator("brute", scene);
  ManylightConfig config = small_clustered_config();
  ManylightRenderer renderer(scene, *accel, config);
  const VisibilityClusters& vc = renderer.clusters();
  const size_t nl = vc.vpl_cluster_count();
  ASSERT_EQ(vc.shading.size(), 16u);
  ASSERT_EQ(nl, 16u);
  bool some_occluded = false, some_visible = false;
  for (size_t s = 0; s < vc.shading.size(); ++s) {
    const DiscreteDistribution& choice = vc.vpl_cluster_choice[s];
    ASSERT_EQ(choice.size(), nl);
    double sum = 0;
    for (size_t l = 0; l < nl; ++l) {
      EXPECT_GT(choice.probability(l), 0.0);
      sum += choice.probability(l);
      const float r = vc.r[s * nl + l];
      EXPECT_GE(r, 0.0f);
      EXPECT_LE(r, 1.0f);
      some_occluded |= r < 1.0f;
      some_visible |= r > 0.0f;
    }
    // Integer ranges of 2^53 units: the probabilities (the renderer's weights) sum to 1 exactly.
    EXPECT_EQ(sum, 1.0);
    EXPECT_EQ(choice.bits(), 53);
  }
  EXPECT_TRUE(some_occluded);
  EXPECT_TRUE(some_visible);
  EXPECT_GT(vc.shadow_rays, 0u);
}

// Fig. 1(b): r of a cluster pair is the visible fraction of its member pairs that face each
// other (t > 0): checked against that fraction computed over every member pair. The other
// tests only ask that some r is below 1 and some above 0; the estimator is unbiased for any r,
// so an r that counted the occluded pairs instead of the visible ones passed every test while
// it made proposed skip the rays it should trace.
TEST(ManylightVisibilityClusters, RIsTheVisibleFractionOfTheFacingMemberPairs) {
  const Scene scene = default_scene();
  auto accel = make_accelerator("bvh", scene);
  ManylightConfig config;
  config.width = 16;
  config.height = 12;
  config.vpl_count = 300;
  config.shading_clusters = config.vpl_clusters = 4;
  config.visibility_samples = 1024;
  config.refine_samples = 0;
  const VplSet vpls = generate_vpls(scene, *accel, config);
  const std::vector<ShadingPoint> points = generate_shading_points(scene, *accel, config);
  const VisibilityClusters vc = build_visibility_clusters(scene, *accel, points, vpls, config);
  const size_t nl = vc.vpl_cluster_count();
  const float offset = 1e-4f * length(scene.bounds().diagonal());
  size_t checked = 0, decisive = 0;
  for (size_t s = 0; s < vc.shading.size(); ++s)
    for (size_t l = 0; l < nl; ++l) {
      RayBatch rays;
      for (uint32_t i = vc.shading.begin[s]; i < vc.shading.begin[s + 1]; ++i)
        for (uint32_t j = vc.lights.begin[l]; j < vc.lights.begin[l + 1]; ++j) {
          const ShadingPoint& sp = points[vc.shading.order[i]];
          const Vpl& v = vpls.vpls[vc.lights.order[j]];
          if (channel_mean(tentative_contribution(scene, sp, v, 0.0f)) > 0.0f) rays.push_back(shadow_ray(sp, v, offset));
        }
      const double facing = double(rays.size()) / double(vc.shading.count(s) * vc.lights.count(l));
      if (facing < 0.1) continue;  // r rests on few of the 1024 samples
      std::vector<uint8_t> occluded;
      accel->occluded(rays, occluded);
      const double visible = double(std::count(occluded.begin(), occluded.end(), uint8_t(0))) / double(rays.size());
      // The 1024 samples draw member pairs with replacement: r is binomial around `visible`.
      const double se = std::sqrt(visible * (1.0 - visible) / (1024.0 * facing));
      EXPECT_NEAR(vc.r[s * nl + l], visible, 5.0 * se + 1e-6) << "pair " << s << ", " << l;
      ++checked;
      decisive += std::fabs(visible - 0.5) > 0.2;  // where counting the occluded ones would show
    }
  EXPECT_GE(checked, 8u);
  EXPECT_GE(decisive, 4u);
}

// Fig. 1(c): a VPL cluster's sampling weight is its estimated contribution times its average
// visibility (sec. 3; rayscout floors r at r_floor). With r_floor = 0, a cluster whose every
// sampled facing pair was occluded (r = 0, so its contribution was seen: C > 0) keeps only the
// uniform share mix |V| / N; the others share the rest. Weighting by C alone passed the other tests.
TEST(ManylightVisibilityClusters, AnOccludedClusterGetsOnlyTheUniformShare) {
  const Scene scene = default_scene();
  auto accel = make_accelerator("bvh", scene);
  ManylightConfig config = small_clustered_config();
  config.r_floor = 0.0f;
  config.uniform_mix = 0.1f;
  ManylightRenderer renderer(scene, *accel, config);
  const VisibilityClusters& vc = renderer.clusters();
  const size_t nl = vc.vpl_cluster_count();
  const double n = double(renderer.vpls().vpls.size());
  size_t occluded = 0;
  for (size_t s = 0; s < vc.shading.size(); ++s)
    for (size_t l = 0; l < nl; ++l) {
      const double uniform = double(config.uniform_mix) * double(vc.lights.count(l)) / n;
      const double p = vc.vpl_cluster_choice[s].probability(l);
      if (vc.r[s * nl + l] == 0.0f) {
        EXPECT_NEAR(p, uniform, 1e-12) << "pair " << s << ", " << l;
        ++occluded;
      } else {
        EXPECT_GE(p, uniform - 1e-12) << "pair " << s << ", " << l;
      }
    }
  EXPECT_GT(occluded, 0u);
}

// Cluster pair ids are 32-bit: more pairs than that are an input error, before any of the
// ~40 bytes a pair are allocated (70000 x 70000 pairs asked for ~200 GB and then wrapped ids).
TEST(ManylightVisibilityClusters, MorePairsThan32BitIdsAreAnInputError) {
  const Scene scene = default_scene();
  auto accel = make_accelerator("brute", scene);
  const size_t n = 70000;  // n^2 > 2^32
  std::vector<ShadingPoint> points(n);
  VplSet vpls;
  vpls.vpls.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const float x = float(i % 265) / 265.0f, z = float(i / 265) / 265.0f;
    points[i].position = Vec3(2.0f * x - 1.0f, 0.0f, 2.0f * z - 1.0f);
    points[i].normal = Vec3(0.0f, 1.0f, 0.0f);
    points[i].weight = Vec3(1.0f);
    vpls.vpls[i].position = Vec3(2.0f * x - 1.0f, 1.9f, 2.0f * z - 1.0f);
  }
  ManylightConfig config;
  config.shading_clusters = config.vpl_clusters = 1 << 17;
  try {
    build_visibility_clusters(scene, *accel, points, vpls, config);
    FAIL() << "built";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cluster pairs, more than 2^32 - 1"), std::string::npos) << e.what();
  }
}

// Fig. 1(c) with rayscout's floor (docs/manylight.md, pmf): a pair's sampling weight is
// C max(r, r_floor). With refinement off, r and C do not depend on r_floor, so the weights C
// read from an r_floor = 1 run (visibility ignored) predict every other floor's pmf; and an
// occluded pair (r = 0, its C seen > 0) keeps more than the uniform share. Weighting by C r
// (the floor dropped) passed every other test.
TEST(ManylightVisibilityClusters, RFloorKeepsOccludedPairsAboveTheUniformShare) {
  const Scene scene = default_scene();
  auto accel = make_accelerator("bvh", scene);
  ManylightConfig config = small_clustered_config();
  config.refine_samples = 0;
  config.uniform_mix = 0.1f;
  auto clusters_with_floor = [&](float r_floor) {
    ManylightConfig c = config;
    c.r_floor = r_floor;
    return ManylightRenderer(scene, *accel, c).clusters();
  };
  const VisibilityClusters ones = clusters_with_floor(1.0f), floored = clusters_with_floor(0.25f);
  ASSERT_EQ(ones.r, floored.r);
  const size_t nl = ones.vpl_cluster_count();
  const double n = double(ManylightRenderer(scene, *accel, config).vpls().vpls.size());
  const double mix = config.uniform_mix;
  size_t occluded = 0, predicted = 0;
  for (size_t s = 0; s < ones.shading.size(); ++s) {
    std::vector<double> c(nl), w(nl);
    double row = 0;
    for (size_t l = 0; l < nl; ++l) {
      const double uniform = mix * double(ones.lights.count(l)) / n;
      c[l] = std::max(0.0, ones.vpl_cluster_choice[s].probability(l) - uniform) / (1.0 - mix);  // C / sum C
      w[l] = c[l] * std::max(double(ones.r[s * nl + l]), 0.25);
      row += w[l];
      if (ones.r[s * nl + l] == 0.0f) {
        EXPECT_GT(ones.vpl_cluster_choice[s].probability(l), uniform + 1e-9) << "pair " << s << ", " << l;
        ++occluded;
      }
    }
    if (!(row > 0)) continue;
    for (size_t l = 0; l < nl; ++l) {
      const double expect = (1.0 - mix) * w[l] / row + mix * double(ones.lights.count(l)) / n;
      EXPECT_NEAR(floored.vpl_cluster_choice[s].probability(l), expect, 1e-6) << "pair " << s << ", " << l;
      ++predicted;
    }
  }
  EXPECT_GT(occluded, 0u);
  EXPECT_GT(predicted, 0u);
}

// A light path from a point light carries its whole power 4 pi I / pdf (start_path); its first
// surface vertex keeps that flux. The path starts alone were checked: a flux of I / pdf passed
// every test (the default scene's indirect light comes mostly from its area light).
TEST(ManylightVpls, APointLightsPathCarriesItsWholePower) {
  Scene scene = default_scene();
  scene.emissive_triangles.clear();  // the point light alone: pdf = 1
  for (Material& m : scene.materials) m.emission = Vec3(0.0f);
  ASSERT_EQ(scene.point_lights.size(), 1u);
  auto accel = make_accelerator("bvh", scene);
  ManylightConfig config;
  config.vpl_count = 400;
  config.max_vpl_bounces = 1;  // every surface VPL is the first vertex of its path
  const VplSet set = generate_vpls(scene, *accel, config);
  const Vec3 start = scene.point_lights[0].intensity * (1.0f / float(set.light_paths));
  size_t surface = 0;
  for (const Vpl& v : set.vpls) {
    if (v.kind == Vpl::Kind::Point) {
      EXPECT_NEAR(v.power.x, start.x, 1e-6 * start.x);
      continue;
    }
    ASSERT_EQ(v.kind, Vpl::Kind::Surface);
    ++surface;
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(v.power[c], 4 * std::numbers::pi_v<float> * start[c], 1e-5 * 4 * std::numbers::pi_v<float> * start[c]);
  }
  EXPECT_GT(surface, set.light_paths / 2);
}

// Fig. 1(c): a VPL cluster's weight is its members' summed contribution, the mean of the sampled
// pairs times the member count. Three equal VPLs, clustered {A} and {B, C}: cluster A has
// probability 1/3, not 1/2 as the mean alone gives (which passed every other test; balanced
// clusters hide it).
TEST(ManylightVisibilityClusters, AClustersWeightSumsItsMembers) {
  const Scene scene = default_scene();
  auto accel = make_accelerator("brute", scene);
  std::vector<ShadingPoint> points(1);
  points[0].position = Vec3(0.0f, 0.01f, 0.0f);
  points[0].normal = points[0].wo = Vec3(0.0f, 1.0f, 0.0f);
  points[0].weight = Vec3(1.0f);
  VplSet vpls;
  vpls.light_paths = 1;
  for (float x : {-0.5f, 0.5f, 0.5f}) {  // mirror images: equal contributions
    Vpl v;
    v.position = Vec3(x, 1.0f, 0.0f);
    v.power = Vec3(1.0f);
    vpls.vpls.push_back(v);
  }
  ManylightConfig config;
  config.shading_clusters = 1;
  config.vpl_clusters = 2;
  config.r_floor = 1.0f;  // weights by contribution alone, whatever the visibility
  const VisibilityClusters vc = build_visibility_clusters(scene, *accel, points, vpls, config);
  ASSERT_EQ(vc.vpl_cluster_count(), 2u);
  for (size_t l = 0; l < 2; ++l) {
    const double share = double(vc.lights.count(l)) / 3.0;
    EXPECT_NEAR(vc.vpl_cluster_choice[0].probability(l), share, 1e-12) << "cluster " << l;
  }
  EXPECT_NE(vc.lights.count(0), vc.lights.count(1));
}

// Refinement (docs/manylight.md): extra rays go to the pairs whose visibility is mixed
// (0 < r < 1) and whose weight is at least their row's mean. The weights of the first estimate
// are read back from a run without refinement (pmf = (1 - mix) w / row + mix |V| / N); the
// other run must refine exactly those pairs. Refining the light pairs instead passed every test.
TEST(ManylightVisibilityClusters, RefinementPicksTheMixedPairsOfAboveMeanWeight) {
  const Scene scene = default_scene();
  auto accel = make_accelerator("bvh", scene);
  ManylightConfig config = small_clustered_config();
  config.uniform_mix = 0.1f;
  config.refine_samples = 0;
  ManylightRenderer plain(scene, *accel, config);
  config.refine_samples = 8;
  ManylightRenderer refined(scene, *accel, config);
  const VisibilityClusters& vc = plain.clusters();
  const size_t nl = vc.vpl_cluster_count();
  const double n = double(plain.vpls().vpls.size()), mix = config.uniform_mix;
  size_t surely = 0, maybe = 0;  // above the mean by a margin, or within it
  for (size_t s = 0; s < vc.shading.size(); ++s)
    for (size_t l = 0; l < nl; ++l) {
      const float r = vc.r[s * nl + l];
      if (!(r > 0.0f && r < 1.0f)) continue;
      const double share = (vc.vpl_cluster_choice[s].probability(l) - mix * double(vc.lights.count(l)) / n) / (1 - mix);
      if (share >= 1.0 / double(nl) + 1e-9) ++surely;
      else if (share >= 1.0 / double(nl) - 1e-9) ++maybe;
    }
  EXPECT_GT(surely, 0u);
  EXPECT_GE(refined.clusters().refined_pairs, surely);
  EXPECT_LE(refined.clusters().refined_pairs, surely + maybe);
  EXPECT_EQ(plain.clusters().refined_pairs, 0u);
}

}  // namespace
}  // namespace rayscout
