// The Integrator adapter: passes, RMSE log, skip image, and a reference of the wrong size.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "rayscout/accelerators.h"
#include "rayscout/core/accelerator_options.h"
#include "rayscout/image/image.h"
#include "rayscout/manylight/manylight_integrator.h"
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
  EXPECT_GT(log["records"][7]["rmse"].get<double>(), 0.0);
  EXPECT_GT(log["skip_rate"].get<double>(), 0.0);
  const Image skip = read_image(dir / "skip.pfm");
  ASSERT_EQ(skip.width, 16);
  float max_skip = 0;
  for (const Vec3& p : skip.pixels) max_skip = std::max(max_skip, p.x);
  EXPECT_GT(max_skip, 0.0f);
  EXPECT_LE(max_skip, 1.0f);

  rc.width = 8;  // the reference no longer matches
  EXPECT_THROW(make_manylight_integrator(o)->render(scene, *accel, rc), InputError);
}

TEST(ManylightConfig, VisibilityModeNames) {
  EXPECT_EQ(parse_visibility_mode("veach"), VisibilityMode::Veach);
  EXPECT_EQ(to_string(parse_visibility_mode("conservative")), "conservative");
  EXPECT_THROW(parse_visibility_mode("always"), InputError);
}

}  // namespace
}  // namespace rayscout
