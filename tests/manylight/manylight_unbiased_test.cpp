// Statistical tests: every visibility mode converges to the exact many-light sum of eq. (1).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "exact_sum.h"
#include "generated_scenes.h"
#include "rayscout/accelerators.h"
#include "rayscout/manylight/channel_mean.h"
#include "rayscout/manylight/manylight_renderer.h"
#include "rayscout/scene/load_scene.h"

namespace rayscout {
namespace {

using testing::small_scale;

ManylightConfig small_config() {
  ManylightConfig c;
  c.width = 32;
  c.height = 24;
  c.vpl_count = 400;
  c.shading_clusters = 16;
  c.vpl_clusters = 16;
  c.samples_per_pass = 4;
  c.points_per_round = 4;
  c.t_eval = 1.0;  // fixed costs: calibration timing would make the test nondeterministic
  c.t_skip = 0.2;
  // Unclamped VPLs near a surface give rare huge samples (heavy tails): the sample standard
  // error would understate the spread. Clamping G (in the reference too) bounds every sample
  // without touching what is tested: E[estimate] = the same eq. (1) sum.
  c.clamp_distance = 0.1f;
  return c;
}

/// Eq. (1) summed over every VPL with exact visibility, per pixel.
std::vector<Vec3> exact_sum(const Scene& scene, const Accelerator& accel, const ManylightRenderer& r) {
  return testing::exact_sum(scene, accel, r.shading_points(), r.vpls().vpls, r.config().width, r.config().height,
                            r.config().clamp_distance);
}

/// Region means (8 x 8 pixel blocks, channel-averaged) of an image.
std::vector<double> regions(const std::vector<Vec3>& img, int w, int h) {
  const int bw = 8, nx = w / bw, ny = h / bw;
  std::vector<double> out(size_t(nx) * ny, 0.0);
  for (int y = 0; y < ny * bw; ++y)
    for (int x = 0; x < nx * bw; ++x) out[(y / bw) * nx + x / bw] += channel_mean(img[size_t(y) * w + x]) / (bw * bw);
  return out;
}

/// Mean over `renders` independent renders of `passes` passes each; returns max |mean - ref| / SE
/// over regions (SE = standard error of the mean over renders).
double max_z_score(ManylightRenderer& r, VisibilityMode mode, const std::vector<double>& ref, int renders, int passes) {
  const int w = r.config().width, h = r.config().height;
  std::vector<double> sum(ref.size(), 0.0), sum2(ref.size(), 0.0);
  for (int k = 0; k < renders; ++k) {
    r.reset(mode);
    r.set_seed(1000 + uint64_t(k) * 7919);
    for (int p = 0; p < passes; ++p) r.render_pass();
    const auto reg = regions(r.image().pixels, w, h);
    for (size_t i = 0; i < reg.size(); ++i) { sum[i] += reg[i]; sum2[i] += reg[i] * reg[i]; }
  }
  double worst = 0;
  for (size_t i = 0; i < ref.size(); ++i) {
    const double mean = sum[i] / renders;
    const double var = std::max(0.0, (sum2[i] / renders - mean * mean) * renders / (renders - 1.0));
    const double se = std::sqrt(var / renders);
    const double diff = std::fabs(mean - ref[i]);
    const double z = se > 0 ? diff / se : (diff <= 1e-6 * std::fabs(ref[i]) + 1e-9 ? 0.0 : INFINITY);
    worst = std::max(worst, z);
  }
  return worst;
}

/// The built-in Cornell box with glossy white surfaces (floor, walls, boxes: Phong 20) and a
/// glossy green wall (Phong 80): glossy shading points and glossy VPLs.
Scene glossy_cornell_box() {
  Scene scene = default_scene();
  for (Material& m : scene.materials) {
    if (m.name == "white") { m.type = Material::Type::Glossy; m.diffuse = m.diffuse * 0.6f; m.specular = Vec3(0.3f); m.exponent = 20; }
    if (m.name == "green") { m.type = Material::Type::Glossy; m.diffuse = m.diffuse * 0.5f; m.specular = Vec3(0.4f); m.exponent = 80; }
  }
  return scene;
}

double image_mean(const std::vector<Vec3>& img) {
  double sum = 0;
  for (const Vec3& p : img) sum += channel_mean(p);
  return sum / double(img.size());
}

/// Mean and standard error of the mean of paired differences.
struct PairedDifference {
  double mean = 0, se = 0, exact_mean = 0;
  double z() const { return se > 0 ? mean / se : (mean == 0 ? 0.0 : INFINITY); }
};

/// Common random numbers: render k renders `exact` and then `mode` with the same seed, so
/// both draw the same VPL samples (the renderer's random numbers are keyed by seed, pass,
/// point and sample) and differ only by the visibility estimate; the image-mean difference of
/// each render pair is one observation. The VPL-sampling noise cancels, so the standard error is
/// that of eq. (8)'s skipping alone: a far tighter test than comparing each mode with eq. (1).
PairedDifference paired_difference(ManylightRenderer& r, VisibilityMode mode, int renders, int passes) {
  double sum = 0, sum2 = 0, exact_sum = 0;
  for (int k = 0; k < renders; ++k) {
    double means[2];
    for (int side = 0; side < 2; ++side) {
      r.reset(side == 0 ? VisibilityMode::Exact : mode);
      r.set_seed(5000 + uint64_t(k) * 7919);
      for (int p = 0; p < passes; ++p) r.render_pass();
      means[side] = image_mean(r.image().pixels);
    }
    const double d = means[1] - means[0];
    sum += d;
    sum2 += d * d;
    exact_sum += means[0];
  }
  const double n = renders, mean = sum / n;
  return {mean, std::sqrt(std::max(0.0, (sum2 / n - mean * mean) / (n - 1.0))), exact_sum / n};
}

class ManylightUnbiased : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_ = default_scene();
    accel_ = make_accelerator("brute", scene_);
  }
  Scene scene_;
  std::unique_ptr<Accelerator> accel_;
};

TEST_F(ManylightUnbiased, EveryModeConvergesToTheExactSumWithinFourStandardErrors) {
  ManylightConfig config = small_config();
  ManylightRenderer r(scene_, *accel_, config);
  const auto ref = regions(exact_sum(scene_, *accel_, r), config.width, config.height);
  // 120 at small scale, not 60: the regions' sums are heavy-tailed (a VPL near a surface), and
  // 60 renders underestimated a standard error. Session 50 changed t in the last bits and exact
  // mode, unbiased by construction, reached z = 4.37 at 60 renders, 3.06 at 120, 2.03 at 200 and
  // 1.92 at 400: a bias would grow with the renders instead.
  const int renders = small_scale() ? 120 : 200;
  for (VisibilityMode mode : {VisibilityMode::Exact, VisibilityMode::Veach, VisibilityMode::Conservative,
                              VisibilityMode::Proposed}) {
    const double z = max_z_score(r, mode, ref, renders, 2);
    EXPECT_LT(z, 4.0) << to_string(mode);
    if (mode != VisibilityMode::Exact) EXPECT_GT(r.skip_rate(), 0.05) << to_string(mode) << " skips something";
    else EXPECT_EQ(r.skip_rate(), 0.0);
  }
}

// Each skipping mode minus exact, paired by common random numbers, on a glossy scene: the mean
// difference must be 0 within 4 standard errors. Measured (Release, 120 renders, ~2 s): the SE
// is 0.14-0.29 % of the image mean, so a bias of ~1 % fails. Planted in eq. (8): dividing by
// 1 - 0.98 q instead of 1 - q gives veach z = -12.2 here while the unpaired test above sits at
// its threshold (z = 4.04; it passed with the VPL samples before DiscreteDistribution);
// dropping the division by 1 - q gives z = -36 to -80 (unpaired: 18-42).
TEST_F(ManylightUnbiased, PairedDifferenceToExactIsZeroOnAGlossyScene) {
  const Scene scene = glossy_cornell_box();
  const auto accel = make_accelerator("brute", scene);
  ManylightRenderer r(scene, *accel, small_config());
  const int renders = small_scale() ? 40 : 120;
  for (VisibilityMode mode : {VisibilityMode::Veach, VisibilityMode::Conservative, VisibilityMode::Proposed}) {
    const PairedDifference d = paired_difference(r, mode, renders, 2);
    EXPECT_LT(std::fabs(d.z()), 4.0) << to_string(mode) << ": mean difference " << d.mean << " +- " << d.se
                                     << " (exact's image mean " << d.exact_mean << ")";
    EXPECT_GT(r.skip_rate(), 0.05) << to_string(mode) << " skips something";
    EXPECT_GT(d.se, 0.0) << to_string(mode) << " differs from exact at all";
  }
}

TEST_F(ManylightUnbiased, EpsilonKeepsProposedUnbiasedWhenThePredictionIsZeroOrOne) {
  const int renders = small_scale() ? 60 : 200;
  std::vector<double> ref;
  for (float forced_r : {0.0f, 1.0f}) {
    ManylightConfig config = small_config();
    config.override_r = forced_r;  // a wrong prediction for every occluded (r = 1) or visible (r = 0) pair
    ManylightRenderer r(scene_, *accel_, config);
    if (ref.empty()) ref = regions(exact_sum(scene_, *accel_, r), config.width, config.height);
    EXPECT_LT(max_z_score(r, VisibilityMode::Proposed, ref, renders, 2), 4.0) << "r = " << forced_r;
    EXPECT_GT(r.skip_rate(), 0.2) << "r = " << forced_r;
  }
  // Counter-check that the test can fail: without the floor, r = 1 skips every shadow ray after
  // the first samples and the image converges to the unoccluded sum instead.
  ManylightConfig config = small_config();
  config.override_r = 1.0f;
  config.epsilon = 0.0f;
  ManylightRenderer biased(scene_, *accel_, config);
  EXPECT_GT(max_z_score(biased, VisibilityMode::Proposed, ref, small_scale() ? 30 : 60, 2), 10.0);
}

TEST_F(ManylightUnbiased, ZeroSkipProbabilityEqualsExactBitForBit) {
  ManylightConfig config = small_config();
  config.t_eval = config.t_skip = 1.0;  // t_diff = 0 -> t_hat = 0 -> q = 0 for every sample
  ManylightRenderer r(scene_, *accel_, config);
  r.reset(VisibilityMode::Exact);
  for (int p = 0; p < 3; ++p) r.render_pass();
  const auto exact = r.image().pixels;
  const uint64_t exact_rays = r.shadow_rays_traced();
  r.reset(VisibilityMode::Proposed);
  for (int p = 0; p < 3; ++p) r.render_pass();
  const auto proposed = r.image().pixels;
  EXPECT_EQ(r.shadow_rays_traced(), exact_rays);
  EXPECT_EQ(r.skip_rate(), 0.0);
  for (size_t i = 0; i < exact.size(); ++i) ASSERT_EQ(exact[i], proposed[i]) << "pixel " << i;
}

TEST_F(ManylightUnbiased, ExactModeConvergesPerPixelToTheSum) {
  // Many passes of exact visibility: the per-pixel estimate approaches eq. (1). The geometry
  // term is clamped (in the reference too) so that per-pixel variance is bounded.
  ManylightConfig config = small_config();
  config.samples_per_pass = 16;
  config.clamp_distance = 0.2f;
  ManylightRenderer r(scene_, *accel_, config);
  Image ref(config.width, config.height);
  ref.pixels = exact_sum(scene_, *accel_, r);
  r.reset(VisibilityMode::Exact);
  const auto records = r.render_for(1e9, ref, small_scale() ? 16 : 64);
  // Unbiased Monte Carlo: MSE ~ 1 / passes, so 4x the passes halves the RMSE (with slack).
  const double early = records[records.size() / 4 - 1].rmse, late = records.back().rmse;
  EXPECT_LT(late, 0.7 * early) << "early " << early << " late " << late;
  double ref_rms = 0;
  for (const Vec3& v : ref.pixels) ref_rms += channel_mean(v) * channel_mean(v);
  ref_rms = std::sqrt(ref_rms / ref.pixels.size());
  EXPECT_LT(late, 0.1 * ref_rms);
}

}  // namespace
}  // namespace rayscout
