// Calibration of t_eval and t_skip (sec. 5) and what the renderer does when skipping saves nothing.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "generated_scenes.h"
#include "rayscout/accelerators.h"
#include "rayscout/manylight/manylight_integrator.h"
#include "rayscout/manylight/manylight_renderer.h"
#include "rayscout/scene/load_scene.h"

namespace rayscout {
namespace {

TEST(ManylightCalibration, ZeroContributionSamplesAreChargedTSkip) {
  // 100 samples, 50 with t > 0: the q = 1 pass took 2 s, so t_skip = 0.02 s; the q = 0 pass
  // took 10 s = 50 t_eval + 50 * 0.02 s (eq. 11's cost model), so t_eval = 0.18 s.
  const SampleCosts c = calibrated_costs(10.0, 2.0, 100, 50);
  EXPECT_DOUBLE_EQ(c.t_skip, 0.02);
  EXPECT_DOUBLE_EQ(c.t_eval, 0.18);
}

TEST(ManylightCalibration, AShadowRayMeasuredFreeDisablesSkippingAndSaysSo) {
  // Timing noise: the q = 0 pass ran faster than the q = 1 pass. t_eval is held at t_skip,
  // so t_hat (eq. 16) is 0 and every sample is traced (q = 0): said, not silent.
  const SampleCosts c = calibrated_costs(1.9, 2.0, 100, 50);
  EXPECT_EQ(c.t_eval, c.t_skip);
  EXPECT_EQ(t_hat(c.t_eval, c.t_skip, 0.0), 0.0);
  ManylightTimings tm;
  tm.t_eval = c.t_eval;
  tm.t_skip = c.t_skip;
  tm.calibrated = true;
  EXPECT_NE(skipping_saves_nothing_warning(VisibilityMode::Proposed, tm).find("traces every sample as exact does"),
            std::string::npos);
  EXPECT_NE(skipping_saves_nothing_warning(VisibilityMode::Veach, tm).find("--visibility veach"), std::string::npos);
  EXPECT_EQ(skipping_saves_nothing_warning(VisibilityMode::Exact, tm), "");
  tm.t_eval = 0.03;
  EXPECT_EQ(skipping_saves_nothing_warning(VisibilityMode::Proposed, tm), "");
  tm.t_eval = tm.t_skip;
  tm.calibrated = false;  // given costs: the CLI checks those (--costs)
  EXPECT_EQ(skipping_saves_nothing_warning(VisibilityMode::Proposed, tm), "");
  // No sample of the calibration subset traces a ray: its cost is unmeasured, not guessed.
  const SampleCosts none = calibrated_costs(2.1, 2.0, 100, 0);
  EXPECT_EQ(none.t_eval, none.t_skip);
}

// A quad lit from behind: no VPL reaches a shading point, so calibration traces no ray and
// measures nothing for it. The run says that skipping is off instead of skipping nothing silently.
TEST(ManylightCalibration, TheIntegratorWarnsWhenCalibrationFindsNothingToSave) {
  Scene scene = testing::scene_from_triangles({Triangle{{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}},
                                               Triangle{{-1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}});
  scene.point_lights[0].position = Vec3{0, 0, -1};
  auto accel = make_accelerator("brute", scene);
  RenderConfig rc;
  rc.width = rc.height = 8;
  ManylightRunOptions o;
  o.config.vpl_count = 50;
  o.config.mode = VisibilityMode::Proposed;
  o.passes = 1;
  o.verbose = false;
  ::testing::internal::CaptureStderr();
  make_manylight_integrator(o)->render(scene, *accel, rc);
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("manylight: warning: calibration measured no time for the shadow ray"), std::string::npos)
      << err;
}

// The run's summary says where the costs came from; exact has none (it printed "calibration
// 0.00 s, t_eval 0 us, t_skip 0 us", and its log t_eval_us 0, as if a ray cost nothing).
TEST(ManylightCalibration, TheSummaryNamesTheCostsSource) {
  const Scene scene = default_scene();
  auto accel = make_accelerator("brute", scene);
  RenderConfig rc;
  rc.width = rc.height = 8;
  const auto log = std::filesystem::temp_directory_path() / "rayscout_manylight_costs_log.json";
  auto summary = [&](VisibilityMode mode, double t_eval, double t_skip) {
    ManylightRunOptions o;
    o.config.vpl_count = 50;
    o.config.mode = mode;
    o.config.t_eval = t_eval;
    o.config.t_skip = t_skip;
    o.passes = 1;
    o.rmse_log = log.string();
    ::testing::internal::CaptureStderr();
    make_manylight_integrator(o)->render(scene, *accel, rc);
    return ::testing::internal::GetCapturedStderr();
  };
  const std::string exact = summary(VisibilityMode::Exact, 0, 0);
  EXPECT_NE(exact.find("no t_eval, t_skip (exact never skips a shadow ray)"), std::string::npos) << exact;
  EXPECT_EQ(exact.find("t_eval 0"), std::string::npos) << exact;
  const nlohmann::json j = nlohmann::json::parse(std::ifstream(log));
  EXPECT_TRUE(j["t_eval_us"].is_null());
  EXPECT_TRUE(j["t_skip_us"].is_null());
  const std::string given = summary(VisibilityMode::Proposed, 0.7e-6, 0.25e-6);
  EXPECT_NE(given.find("; t_eval 0.7 us, t_skip 0.25 us (given)"), std::string::npos) << given;
  EXPECT_EQ(given.find("calibration"), std::string::npos) << given;
  const std::string calibrated = summary(VisibilityMode::Veach, 0, 0);
  EXPECT_NE(calibrated.find("; calibration "), std::string::npos) << calibrated;
  EXPECT_NE(calibrated.find(" s, t_eval "), std::string::npos) << calibrated;
  std::filesystem::remove(log);
}

// One cost alone is not a cost model: both are calibrated, whether a pass or the caller asks.
// (render_pass() once took a given t_eval with t_skip = 0, where calibrate() measured both.)
TEST(ManylightCalibration, OneGivenCostAloneIsNotUsed) {
  const Scene scene = default_scene();
  auto accel = make_accelerator("brute", scene);
  ManylightConfig c;
  c.width = c.height = 8;
  c.vpl_count = 50;
  c.t_eval = 1e-6;
  ManylightRenderer r(scene, *accel, c);
  EXPECT_EQ(r.timings().t_eval, 0.0);
  r.render_pass();
  EXPECT_TRUE(r.timings().calibrated);
  EXPECT_GT(r.timings().t_skip, 0.0);
  c.t_skip = 2e-7;  // both: used as given, never measured
  ManylightRenderer given(scene, *accel, c);
  given.render_pass();
  EXPECT_FALSE(given.timings().calibrated);
  EXPECT_EQ(given.timings().t_eval, 1e-6);
  EXPECT_EQ(given.timings().t_skip, 2e-7);
}

}  // namespace
}  // namespace rayscout
