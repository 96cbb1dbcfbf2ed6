// ManylightConfig: every tunable of the many-light renderer, with documented defaults.
#pragma once

#include <cstdint>
#include <string>
#include <utility>

namespace rayscout {

/// How the visibility of a sampled VPL is evaluated (Nabata & Iwasaki 2019, sec. 3 and 5).
enum class VisibilityMode {
  Exact,         ///< q = 0: always trace the shadow ray (the baseline)
  Veach,         ///< r_i = 0 and (v_i - r_i)^2 -> 1 in eq. (15): efficiency-optimised RR
  Conservative,  ///< (v_i - r_i)^2 -> max((1 - r_i)^2, r_i^2) (the paper's Table 3 ablation)
  Proposed,      ///< (v_i - r_i)^2 -> max(eps, r_i (1 - r_i)) (sec. 4.2)
};

/// Every mode with its name (the values of --visibility).
inline constexpr std::pair<const char*, VisibilityMode> kVisibilityModes[] = {
    {"exact", VisibilityMode::Exact}, {"veach", VisibilityMode::Veach},
    {"conservative", VisibilityMode::Conservative}, {"proposed", VisibilityMode::Proposed}};

/// The mode named `name` in kVisibilityModes; throws InputError for any other name.
VisibilityMode parse_visibility_mode(const std::string& name);
std::string to_string(VisibilityMode mode);

/// Most member pairs sampled per cluster pair (visibility, refinement, contribution): one
/// pair's visibility samples are traced as one batch.
inline constexpr int kMaxPairSamples = 65536;

/// Tunables of instant radiosity, VisibilityCluster and probabilistic visibility.
struct ManylightConfig {
  // Image and shading points.
  int width = 640;             ///< pixels
  int height = 360;            ///< pixels
  int spp = 1;                 ///< shading points per pixel (jittered primary rays)
  int max_mirror_bounces = 4;  ///< camera paths follow perfect mirrors this often

  // VPLs (instant radiosity, Keller 1997).
  size_t vpl_count = 10000;    ///< target number of VPLs (whole light paths are kept, so a few more)
  int max_vpl_bounces = 5;     ///< surface vertices per light path at most (Russian roulette before)
  /// Geometry-term clamping: G uses max(d^2, clamp_distance^2). 0 = off (the default, unbiased
  /// with respect to eq. (1)); a positive value removes VPL singularities but darkens corners.
  float clamp_distance = 0.0f;

  // VisibilityCluster (Wu & Chuang 2013).
  int shading_clusters = 512;  ///< number of shading-point clusters (rounded to a power of two)
  int vpl_clusters = 512;      ///< number of VPL clusters (rounded to a power of two)
  float normal_weight = 0.3f;  ///< weight of the normal against position (scene diagonal = 1)
  int visibility_samples = 4;  ///< shadow rays per (shading cluster, VPL cluster) pair
  int contribution_samples = 16;  ///< extra ray-free member pairs estimating a pair's contribution
  int refine_samples = 8;      ///< extra rays for uncertain (0 < r < 1), important pairs; 0 = off
  float r_floor = 0.1f;        ///< sampling weight uses max(r, r_floor): a pair seen occluded stays samplable
  float uniform_mix = 0.1f;    ///< defensive mix with uniform-over-VPLs: every pdf > 0 (unbiased)

  // Probabilistic visibility (Nabata & Iwasaki 2019).
  VisibilityMode mode = VisibilityMode::Proposed;
  float epsilon = 0.1f;        ///< floor of (v - r)^2 in `proposed` (sec. 4.2)
  int samples_per_pass = 1;    ///< VPL samples per shading point per pass (N of eq. 2)
  int points_per_round = 16;   ///< points per cluster per wavefront round (stats update between rounds)
  double t_eval = 0.0;         ///< seconds per sample with the shadow ray; used only with t_skip
  double t_skip = 0.0;         ///< seconds per sample without it; unless both are > 0, both are calibrated
  int calibration_stride = 4;  ///< calibration renders every stride-th pixel row and column

  /// Clock of time budgets and calibration: false = wall clock; true = process CPU time
  /// (all threads), which a shared machine disturbs less.
  bool cpu_clock = false;

  uint64_t seed = 1;           ///< all randomness derives from it (thread-count independent)
  /// Test hook: when in [0, 1], every cluster-pair visibility r is replaced by this value
  /// (to build cases where r is wrong, e.g. r = 1 for occluded pairs). -1 = off.
  float override_r = -1.0f;
};

}  // namespace rayscout
