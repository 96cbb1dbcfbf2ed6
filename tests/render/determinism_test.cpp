// Same seed, same image, bit for bit: across accelerators, thread counts and repeated runs.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include "rayscout/accelerators.h"
#include "rayscout/core/input_error.h"
#include "rayscout/render/renderer.h"
#include "rayscout/scene/load_scene.h"
#include "test_scenes.h"

namespace rayscout {
namespace {

// The built-in Cornell box with a mirror short box and a glossy tall box, so that every
// material and ray kind occurs.
Scene test_scene() {
  Scene s = default_scene();
  Material mirror{.name = "test_mirror", .type = Material::Type::Mirror, .specular = Vec3{0.9f}};
  Material glossy{.name = "test_glossy", .type = Material::Type::Glossy, .diffuse = Vec3{0.3f},
                  .specular = Vec3{0.5f}, .exponent = 20};
  const uint32_t m = uint32_t(s.materials.size());
  s.materials.push_back(mirror);
  s.materials.push_back(glossy);
  for (uint32_t i = 0; i < s.triangles.size(); ++i) {
    if (s.material_of(i).emissive()) continue;
    const Vec3 c = s.triangles[i].centroid();
    if (c.y > 0.01f && c.y < 1.9f && std::fabs(c.x) < 0.95f && std::fabs(c.z) < 0.95f)
      s.material_ids[i] = c.x > 0 ? m : m + 1;  // the boxes: right one mirror, left one glossy
  }
  return s;
}

RenderConfig small_config() {
  RenderConfig c;
  c.width = testing::small_scale() ? 12 : 32;
  c.height = testing::small_scale() ? 10 : 24;
  c.spp = 3;
  c.seed = 11;
  c.light_samples = 2;
  c.ao_samples = 2;
  return c;
}

std::vector<std::unique_ptr<Integrator>> all_integrators() {
  std::vector<std::unique_ptr<Integrator>> v;
  v.push_back(make_direct_integrator());
  v.push_back(make_area_integrator());
  v.push_back(make_ao_integrator());
  v.push_back(make_path_integrator());
  return v;
}

// Index of the first pixel that differs in any bit, or -1.
long first_difference(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height) return 0;
  for (size_t i = 0; i < a.pixels.size(); ++i)
    if (std::memcmp(&a.pixels[i], &b.pixels[i], sizeof(Vec3)) != 0) return long(i);
  return -1;
}

TEST(Determinism, EveryAcceleratorGivesBruteForcesImage) {
  const Scene scene = test_scene();
  const RenderConfig cfg = small_config();
  const auto brute = make_accelerator("brute", scene);
  for (const auto& integrator : all_integrators()) {
    const Image ref = integrator->render(scene, *brute, cfg);
    double sum = 0;
    for (const Vec3& p : ref.pixels) sum += p.x + p.y + p.z;
    EXPECT_GT(sum, 0.0) << integrator->name() << ": black image";
    for (const auto& info : accelerators()) {
      if (info.name == "brute") continue;
      const auto accel = make_accelerator(info.name, scene);
      const Image img = integrator->render(scene, *accel, cfg);
      EXPECT_EQ(first_difference(ref, img), -1) << integrator->name() << " on " << info.name;
    }
  }
}

TEST(Determinism, ThreadCountDoesNotChangeTheImage) {
  const Scene scene = test_scene();
  const RenderConfig cfg = small_config();
  for (const auto& info : accelerators()) {
    const auto accel = make_accelerator(info.name, scene);
    for (const auto& integrator : all_integrators()) {
      Image one, two;
      {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one = integrator->render(scene, *accel, cfg);
      }
      {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
        two = integrator->render(scene, *accel, cfg);
      }
      EXPECT_EQ(first_difference(one, two), -1) << integrator->name() << " on " << info.name;
    }
  }
}

// Enough rays that shading and accumulation are split into many parallel blocks.
TEST(Determinism, ThreadCountDoesNotChangeALargerImage) {
  const Scene scene = test_scene();
  RenderConfig cfg = small_config();
  cfg.width = testing::small_scale() ? 32 : 96;
  cfg.height = testing::small_scale() ? 32 : 64;
  cfg.spp = 4;
  const auto accel = make_accelerator("brute", scene);
  const auto path = make_path_integrator();
  Image one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = path->render(scene, *accel, cfg);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = path->render(scene, *accel, cfg);
  }
  EXPECT_EQ(first_difference(one, two), -1);
}

TEST(Determinism, SeedSelectsTheImage) {
  const Scene scene = test_scene();
  RenderConfig cfg = small_config();
  const auto accel = make_accelerator("brute", scene);
  const auto path = make_path_integrator();
  const Image a = path->render(scene, *accel, cfg), b = path->render(scene, *accel, cfg);
  EXPECT_EQ(first_difference(a, b), -1);
  cfg.seed = 12;
  EXPECT_NE(first_difference(a, path->render(scene, *accel, cfg)), -1);
}

// The same scene in other units: every length times s (a power of two, so exact), point-light
// intensities times s^2 (same irradiance), area emission unchanged (radiance).
Scene scaled(Scene s, float scale) {
  for (Triangle& t : s.triangles) t = {t.v0 * scale, t.v1 * scale, t.v2 * scale};
  s.camera.eye = s.camera.eye * scale;
  s.camera.look_at = s.camera.look_at * scale;
  s.camera.lens_radius *= scale;
  s.camera.focus_distance *= scale;
  for (PointLight& l : s.point_lights) {
    l.position = l.position * scale;
    l.intensity = l.intensity * (scale * scale);
  }
  return s;
}

double mean(const Image& image) {
  return (testing::mean_channel(image, 0) + testing::mean_channel(image, 1) + testing::mean_channel(image, 2)) / 3.0;
}

// Offsets and lengths follow the scene: a 1e-8 scene once lost its indirect light to a fixed
// ray offset, and edges of 1e10 overflowed the normal's length (shading with the view direction).
TEST(Determinism, ImagesDoNotDependOnTheSceneScale) {
  const Scene unit = test_scene();
  const RenderConfig cfg = small_config();
  for (const float scale : {0x1p-27f, 0x1p33f}) {
    const Scene other = scaled(unit, scale);
    for (const auto& integrator : all_integrators()) {
      const double a = mean(integrator->render(unit, *make_accelerator("bvh", unit), cfg));
      const double b = mean(integrator->render(other, *make_accelerator("bvh", other), cfg));
      EXPECT_GT(a, 0.01);
      EXPECT_NEAR(b, a, 0.005 * a) << integrator->name() << " at scale " << scale;
    }
  }
}

// Settings a render cannot use are refused before any work, not replaced silently.
TEST(RenderConfig, ValidateRefusesSettingsOutOfRange) {
  const Scene scene = test_scene();
  const auto accel = make_accelerator("brute", scene);
  const auto ao = make_ao_integrator();
  auto refused = [&](auto change) {
    RenderConfig cfg = small_config();
    change(cfg);
    EXPECT_THROW(cfg.validate(), InputError);
    EXPECT_THROW(ao->render(scene, *accel, cfg), InputError);
  };
  EXPECT_NO_THROW(small_config().validate());
  refused([](RenderConfig& c) { c.width = 0; });
  refused([](RenderConfig& c) { c.spp = 1 << 17; });
  refused([](RenderConfig& c) { c.width = c.height = 1 << 15; c.spp = 4; });  // 2^32 rays
  // The message gives the values (it said only "width * height * spp must stay below 2^32").
  try {
    RenderConfig cfg = small_config();
    cfg.width = cfg.height = 1 << 15;
    cfg.spp = 4;
    cfg.validate();
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("render: width 32768 x height 32768 x spp 4 = 4294967296 camera samples, "
                                         "more than 2^32 - 1"),
              std::string::npos)
        << e.what();
  }
  refused([](RenderConfig& c) { c.ao_samples = 0; });
  refused([](RenderConfig& c) { c.max_batch_rays = -1; });  // was the default, silently
  // An infinite offset once rendered an AO image of open sky (every ray left from infinity).
  for (const float bad : {-1.0f, kInfinity, std::numeric_limits<float>::quiet_NaN()}) {
    refused([&](RenderConfig& c) { c.ray_epsilon = bad; });
    refused([&](RenderConfig& c) { c.ao_radius = bad; });
  }
}

// Every pixel of every integrator is a finite, non-negative radiance: mirrors, a glossy lobe,
// point and area lights, a thin lens, several bounces and Russian roulette, a non-square spp.
TEST(Determinism, EveryPixelIsFiniteAndNonNegative) {
  Scene scene = test_scene();
  scene.camera.lens_radius = 0.05f;
  scene.camera.focus_distance = length(scene.camera.look_at - scene.camera.eye);
  RenderConfig cfg = small_config();
  cfg.spp = 5;
  cfg.max_depth = 6;
  cfg.rr_depth = 1;
  const auto accel = make_accelerator("brute", scene);
  for (const auto& integrator : all_integrators()) {
    const Image img = integrator->render(scene, *accel, cfg);
    for (size_t i = 0; i < img.pixels.size(); ++i) {
      const Vec3& p = img.pixels[i];
      ASSERT_TRUE(is_finite(p) && p.x >= 0 && p.y >= 0 && p.z >= 0) << integrator->name() << " pixel " << i;
    }
  }
}

// Renders cfg's path-traced image whole, then with max_batch_rays = max_batch: expects the same
// image up to float summation order and returns the sizes of the second render's camera batches.
std::vector<size_t> camera_batches_of_split_render(RenderConfig cfg, long max_batch) {
  const Scene scene = test_scene();
  const auto accel = make_accelerator("brute", scene);
  const auto path = make_path_integrator();
  const Image whole = path->render(scene, *accel, cfg);
  std::vector<size_t> sizes;
  cfg.max_batch_rays = max_batch;
  cfg.on_batch = [&](const BatchInfo& info, const RayBatch& rays) {
    if (info.kind == "primary") sizes.push_back(rays.size());
  };
  const Image split = path->render(scene, *accel, cfg);
  for (size_t i = 0; i < whole.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(split.pixels[i][c], whole.pixels[i][c], 1e-5f * std::max(1.0f, whole.pixels[i][c])) << i;
  return sizes;
}

// Passes of whole samples (max_batch_rays), each tracing one camera batch.
TEST(Batches, SamplePassesBoundTheBatchSize) {
  RenderConfig cfg = small_config();
  cfg.spp = 5;
  const size_t pixels = size_t(cfg.width) * size_t(cfg.height);
  // 2 samples per pass: 3 passes, the last of one sample.
  const std::vector<size_t> sizes = camera_batches_of_split_render(cfg, long(pixels) * 2);
  EXPECT_EQ(sizes, (std::vector<size_t>{2 * pixels, 2 * pixels, pixels}));
}

// An image with more pixels than max_batch_rays is traced in bands of rows, one sample per
// pass: no camera batch above the limit.
TEST(Batches, RowBandsBoundTheBatchOfALargeImage) {
  RenderConfig cfg = small_config();
  cfg.spp = 2;
  const int rows = 7;
  ASSERT_EQ(cfg.height % rows, 3);  // the last band is short
  const size_t w = size_t(cfg.width);
  const std::vector<size_t> sizes = camera_batches_of_split_render(cfg, long(w) * rows + long(w) - 1);
  std::vector<size_t> expected;
  for (int band = 0; band < cfg.height; band += rows)  // each band once per sample
    expected.insert(expected.end(), 2, w * size_t(std::min(rows, cfg.height - band)));
  EXPECT_EQ(sizes, expected);
}

TEST(Batches, KindsBouncesAndStats) {
  const Scene scene = test_scene();
  RenderConfig cfg = small_config();
  cfg.max_depth = 2;
  cfg.count = true;
  std::vector<BatchInfo> seen;
  std::vector<size_t> sizes;
  cfg.on_batch = [&](const BatchInfo& info, const RayBatch& rays) {
    seen.push_back(info);
    sizes.push_back(rays.size());
  };
  const auto accel = make_accelerator("brute", scene);
  RenderStats stats;
  make_direct_integrator()->render(scene, *accel, cfg, &stats);
  ASSERT_GE(seen.size(), 4u);
  EXPECT_EQ(seen[0].kind, "primary");
  EXPECT_FALSE(seen[0].occlusion);
  EXPECT_EQ(sizes[0], size_t(cfg.width) * cfg.height * cfg.spp);
  EXPECT_EQ(seen[1].kind, "shadow");
  EXPECT_TRUE(seen[1].occlusion);
  EXPECT_EQ(seen[2].kind, "mirror");
  EXPECT_EQ(seen[2].bounce, 1);
  ASSERT_EQ(stats.batches.size(), seen.size());
  uint64_t total = 0;
  for (size_t i = 0; i < seen.size(); ++i) {
    EXPECT_EQ(stats.batches[i].rays, sizes[i]);
    EXPECT_EQ(stats.batches[i].info.kind, seen[i].kind);
    EXPECT_LE(seen[i].bounce, cfg.max_depth);
    EXPECT_EQ(stats.batches[i].counters.rays, sizes[i]);
    // Brute force tests every ray against every triangle (any hit stops at the first).
    const uint64_t all_pairs = uint64_t(sizes[i]) * scene.triangles.size();
    if (seen[i].occlusion) {
      EXPECT_LE(stats.batches[i].counters.ray_tri_tests, all_pairs) << i;
      EXPECT_GE(stats.batches[i].counters.ray_tri_tests, sizes[i]) << i;
    } else {
      EXPECT_EQ(stats.batches[i].counters.ray_tri_tests, all_pairs) << i;
    }
    total += sizes[i];
  }
  EXPECT_EQ(stats.rays(), total);
  // --stats writes this JSON: one entry per batch with its kind and exact counters.
  const auto json = nlohmann::json::parse(stats.to_json());
  ASSERT_EQ(json.at("batches").size(), seen.size());
  for (size_t i = 0; i < seen.size(); ++i) {
    const auto& b = json["batches"][i];
    EXPECT_EQ(b.at("kind"), seen[i].kind);
    EXPECT_EQ(b.at("bounce"), seen[i].bounce);
    EXPECT_EQ(b.at("rays"), sizes[i]);
    EXPECT_EQ(b.at("counters").at("rays"), sizes[i]);
  }
  EXPECT_EQ(json.at("rays"), total);

  seen.clear();
  make_ao_integrator()->render(scene, *accel, cfg);
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_EQ(seen[1].kind, "ao");
  seen.clear();
  make_path_integrator()->render(scene, *accel, cfg);
  EXPECT_EQ(seen.back().bounce, cfg.max_depth);
  EXPECT_EQ(seen[2].kind, "path");
}

// A path's last diffuse bounce (bounce max_depth - 1) sends shadow rays but no bounce ray:
// the vertex after it could only add emission, which after a diffuse bounce comes from
// next-event estimation. In a closed emissive diffuse sphere: primary and shadow rays at
// bounce 0, path and shadow rays at bounce 1, nothing at bounce 2 = max_depth.
TEST(Batches, PathTracesNoRaysPastItsLastDiffuseBounce) {
  Scene scene;
  testing::add_part(scene, testing::inward_sphere({0, 0, 0}, 1.0f, 1),
                    Material{.diffuse = Vec3{0.5f}, .emission = Vec3{1.0f}});
  scene.camera.eye = {0.1f, 0.0f, 0.05f};
  scene.camera.look_at = {1.0f, 0.2f, 0.0f};
  RenderConfig cfg;
  cfg.width = cfg.height = 4;
  cfg.spp = 1;
  std::vector<std::pair<std::string, int>> seen;
  cfg.on_batch = [&](const BatchInfo& info, const RayBatch&) { seen.emplace_back(info.kind, info.bounce); };
  const auto accel = make_accelerator("brute", scene);
  cfg.max_depth = 2;
  make_path_integrator()->render(scene, *accel, cfg);
  const std::vector<std::pair<std::string, int>> two = {{"primary", 0}, {"shadow", 0}, {"path", 1}, {"shadow", 1}};
  EXPECT_EQ(seen, two);
  seen.clear();
  cfg.max_depth = 0;  // emission seen from the camera only
  make_path_integrator()->render(scene, *accel, cfg);
  EXPECT_EQ(seen, (std::vector<std::pair<std::string, int>>{{"primary", 0}}));
}

}  // namespace
}  // namespace rayscout
