// The Integrator adapter: passes, RMSE log, skip image, and a reference of the wrong size.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "rayscout/accelerators.h"
#include "rayscout/core/input_error.h"
#include "rayscout/image/image.h"
#include "rayscout/manylight/channel_mean.h"
#include "rayscout/manylight/manylight_integrator.h"
#include "rayscout/manylight/manylight_renderer.h"
#include "rayscout/scene/load_scene.h"

namespace rayscout {
namespace {

TEST(ManylightIntegrator, WritesImageLogAndSkipImage) {
  const Scene scene = default_scene();
  auto accel = make_accelerator("brute", scene);
  const auto dir = std::filesystem::temp_directory_path() / "rayscout_manylight_test";
  std::filesystem::create_directories(dir);
  RenderConfig rc;
  rc.width = 16;
  rc.height = 12;
  rc.spp = 1;
  // Reference: exact visibility, many passes.
  ManylightRunOptions ref_opts;
  ref_opts.config.vpl_count = 300;
  ref_opts.config.mode = VisibilityMode::Exact;
  ref_opts.passes = 64;
  ref_opts.verbose = false;
  const Image ref = make_manylight_integrator(ref_opts)->render(scene, *accel, rc);
  ASSERT_EQ(ref.pixels.size(), 16u * 12u);
  write_image(ref, dir / "ref.pfm");

  ManylightRunOptions o = ref_opts;
  o.config.mode = VisibilityMode::Proposed;
  o.config.t_eval = 1.0;
  o.config.t_skip = 0.2;
  o.passes = 8;
  o.reference = (dir / "ref.pfm").string();
  o.rmse_log = (dir / "log.json").string();
  o.skip_image = (dir / "skip.pfm").string();
  RenderStats stats;
  std::vector<RenderProgress> progress;  // one report per pass, as the CLI's progress bar needs
  rc.on_progress = [&](const RenderProgress& p) { progress.push_back(p); };
  const Image img = make_manylight_integrator(o)->render(scene, *accel, rc, &stats);
  ASSERT_EQ(progress.size(), 8u);
  for (int i = 0; i < 8; ++i) {
    EXPECT_EQ(progress[i].pass, i);
    EXPECT_EQ(progress[i].passes, 8);
  }
  EXPECT_GT(progress.back().rays_traced, 0u);
  rc.on_progress = nullptr;
  EXPECT_EQ(img.width, 16);
  EXPECT_GT(stats.total_ms, 0.0);
  nlohmann::json log = nlohmann::json::parse(std::ifstream(dir / "log.json"));
  ASSERT_EQ(log["records"].size(), 8u);
  EXPECT_EQ(log["visibility"], "proposed");
  for (size_t i = 0; i < 8; ++i) EXPECT_EQ(log["records"][i]["passes"].get<size_t>(), i + 1);
  // The last record is the returned image against the reference (doubles round-trip in JSON).
  const double final_rmse = compare_images(img, ref).rmse;
  EXPECT_GT(final_rmse, 0.0);
  EXPECT_EQ(log["records"][7]["rmse"].get<double>(), final_rmse);
  const Image skip = read_image(dir / "skip.pfm");
  ASSERT_EQ(skip.width, 16);
  float max_skip = 0;
  for (const Vec3& p : skip.pixels) max_skip = std::max(max_skip, p.x);
  EXPECT_GT(max_skip, 0.0f);
  EXPECT_LE(max_skip, 1.0f);
  // The .pfm holds the rates themselves: the same render (fixed costs, same seed) again.
  ManylightConfig same = o.config;
  same.width = rc.width;
  same.height = rc.height;
  same.spp = rc.spp;
  same.seed = rc.seed;
  ManylightRenderer again(scene, *accel, same);
  again.render_for(1e300, {}, 8);
  const std::vector<float> rates = again.skip_image();
  ASSERT_EQ(rates.size(), skip.pixels.size());
  int between = 0;
  for (size_t i = 0; i < rates.size(); ++i) {
    between += rates[i] > 0.05f && rates[i] < 0.95f;
    ASSERT_EQ(skip.pixels[i].x, rates[i]) << "pixel " << i;
  }
  EXPECT_GT(between, 0);  // a rate an sRGB curve would have changed
  // The log's skip rates are the render's: overall and after the last pass.
  EXPECT_GT(again.skip_rate(), 0.0);
  EXPECT_EQ(log["skip_rate"].get<double>(), again.skip_rate());
  EXPECT_EQ(log["records"][7]["skip_rate"].get<double>(), again.skip_rate());

  rc.width = 8;  // the reference no longer matches
  EXPECT_THROW(make_manylight_integrator(o)->render(scene, *accel, rc), InputError);
}

// A scene made in code whose lights are dark (scene files refuse them when read): an input
// error, not an image of NaN.
TEST(ManylightIntegrator, SceneWithoutALightThatEmitsIsAnInputError) {
  Scene scene = default_scene();
  for (Material& m : scene.materials) m.emission = Vec3{0.0f};
  scene.emissive_triangles.clear();
  for (PointLight& l : scene.point_lights) l.intensity = Vec3{0.0f};
  ASSERT_FALSE(scene.point_lights.empty());
  auto accel = make_accelerator("brute", scene);
  RenderConfig rc;
  rc.width = rc.height = 4;
  ManylightRunOptions o;
  o.config.vpl_count = 10;
  o.passes = 1;
  o.verbose = false;
  try {
    make_manylight_integrator(o)->render(scene, *accel, rc);
    FAIL() << "rendered";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no light that emits"), std::string::npos) << e.what();
  }
}

// Without the uniform mix, a VPL cluster whose estimated contribution is 0 is never drawn
// (its light would be missing from the image): refused, like a floor outside [0, 1].
TEST(ManylightConfig, UniformMixMustBePositiveAndFloorAProbability) {
  const Scene scene = default_scene();
  auto accel = make_accelerator("brute", scene);
  ManylightConfig c;
  c.width = c.height = 4;
  c.vpl_count = 10;
  EXPECT_NO_THROW(ManylightRenderer(scene, *accel, c));
  for (float mix : {0.0f, -0.1f, 1.5f}) {
    ManylightConfig bad = c;
    bad.uniform_mix = mix;
    EXPECT_THROW(ManylightRenderer(scene, *accel, bad), InputError) << "uniform_mix " << mix;
  }
  ManylightConfig bad = c;
  bad.r_floor = 1.5f;
  EXPECT_THROW(ManylightRenderer(scene, *accel, bad), InputError);
}

// A skip image shows the rate in every format: .pfm and .exr store it, a .png's 8-bit pixel
// value is rate * 255 (rounded) after the writer's sRGB encoding.
TEST(ManylightIntegrator, SkipImageStoresTheRateInEveryFormat) {
  const std::vector<float> rates{0.0f, 0.1f, 0.25f, 0.5f, 0.75f, 1.0f};
  const auto dir = std::filesystem::temp_directory_path() / "rayscout_manylight_skip_test";
  std::filesystem::create_directories(dir);
  for (const char* name : {"skip.pfm", "skip.exr", "skip.png", "SKIP.PNG"}) {
    write_image(skip_rate_image(rates, 3, 2, dir / name), dir / name);
    const Image back = read_image(dir / name);
    ASSERT_EQ(back.pixels.size(), rates.size()) << name;
    const bool png = std::string(name).ends_with("png") || std::string(name).ends_with("PNG");
    for (size_t i = 0; i < rates.size(); ++i)
      for (int c = 0; c < 3; ++c) {
        if (png) EXPECT_NEAR(255.0f * linear_to_srgb(back.pixels[i][c]), 255.0f * rates[i], 0.5f) << name << " " << i;
        else EXPECT_EQ(back.pixels[i][c], rates[i]) << name << " " << i;
      }
  }
}

// Shading points and VPLs take their hit distances from the triangle (refine_hit), as the
// render module does: every accelerator gives brute force's image bit for bit, Embree too.
// Embree's own t moved shading points and VPLs by an ulp, which changed the clustering and
// with it every sample (rel. MSE 0.19 to bvh's image at 64 x 48). Jittered pixels (spp 2):
// pixel centres here fall on the walls' diagonals, where Embree may report the other triangle
// of a quad (a tie, as in RealScene.SibenikImageOnEveryAccelerator), and one moved point
// changes the whole clustering.
TEST(ManylightRenderer, EveryAcceleratorGivesTheSameImage) {
  const Scene scene = default_scene();
  ManylightConfig c;
  c.width = 32;
  c.height = 24;
  c.spp = 2;
  c.vpl_count = 400;
  c.shading_clusters = c.vpl_clusters = 16;
  c.t_eval = 1.0;
  c.t_skip = 0.2;
  auto render = [&](const std::string& name) {
    const auto accel = make_accelerator(name, scene);
    ManylightRenderer r(scene, *accel, c);
    r.render_for(1e300, {}, 2);
    return r.image();
  };
  const Image reference = render("brute");
  for (const auto& info : accelerators()) {
    if (info.name == "brute") continue;
    const Image img = render(info.name);
    ASSERT_EQ(img.pixels.size(), reference.pixels.size());
    size_t differing = 0;
    for (size_t i = 0; i < img.pixels.size(); ++i)
      differing += std::memcmp(&img.pixels[i], &reference.pixels[i], sizeof(Vec3)) != 0;
    EXPECT_EQ(differing, 0u) << info.name;
  }
}

// Sec. 4.1: what a pass adds to its clusters' statistics, eqs. (16) and (17). With exact
// visibility every sample with t > 0 is traced (q = 0) and the others enter with q = 1, so the
// samples minus the summed q are the shadow rays; y = t V / p sums to the image's estimate.
// Entering the zero-contribution samples with q = 0, or y without V~, changes only how much is
// skipped later (not the expectation) and passed every other test.
TEST(ManylightRenderer, ClusterStatisticsHoldEachSamplesQAndEstimate) {
  const Scene scene = default_scene();
  auto accel = make_accelerator("bvh", scene);
  ManylightConfig c;
  c.width = 32;
  c.height = 24;
  c.vpl_count = 400;
  c.shading_clusters = c.vpl_clusters = 16;
  c.samples_per_pass = 4;
  c.mode = VisibilityMode::Exact;
  ManylightRenderer r(scene, *accel, c);
  r.render_pass();
  double n = 0, sum_q = 0, sum_y = 0;
  for (const ClusterSampleStats& st : r.cluster_stats()) {
    n += st.n;
    sum_q += st.sum_q;
    sum_y += st.sum_y;
  }
  const Image img = r.image();
  double valid = 0, estimate = 0;
  for (const ShadingPoint& sp : r.shading_points()) {
    if (!sp.valid()) continue;
    ++valid;
    estimate += channel_mean(img.pixels[sp.pixel] - sp.emitted);  // spp 1, no mirror: weight 1
  }
  EXPECT_EQ(n, valid * c.samples_per_pass);
  EXPECT_GT(sum_q, 0.0) << "some samples have t = 0";
  EXPECT_EQ(n - sum_q, double(r.shadow_rays_traced()));
  EXPECT_NEAR(sum_y, estimate * c.samples_per_pass, 1e-4 * sum_y);
}

TEST(ManylightConfig, VisibilityModeNames) {
  EXPECT_EQ(parse_visibility_mode("veach"), VisibilityMode::Veach);
  EXPECT_EQ(to_string(parse_visibility_mode("conservative")), "conservative");
  EXPECT_THROW(parse_visibility_mode("always"), InputError);
}

}  // namespace
}  // namespace rayscout
