// ManylightRenderer: progressive many-light rendering with VisibilityCluster sampling and
// probabilistic visibility (Nabata & Iwasaki 2019, building on Wu & Chuang 2013).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "rayscout/core/accelerator.h"
#include "rayscout/image/image.h"
#include "rayscout/manylight/manylight_config.h"
#include "rayscout/manylight/probabilistic_visibility.h"
#include "rayscout/manylight/shading_points.h"
#include "rayscout/manylight/visibility_cluster.h"
#include "rayscout/manylight/vpl.h"

namespace rayscout {

/// Costs of the preprocess (independent of the sample count; the paper's "Visibility Cluster"
/// column of Table 1) and the calibrated per-sample costs, on config.cpu_clock's clock (wall
/// time, or process CPU time); VisibilityCluster's phases split its measured total in the
/// proportions of their wall times.
struct ManylightTimings {
  double vpl_ms = 0, shading_points_ms = 0, cluster_ms = 0, visibility_ms = 0, pmf_ms = 0;
  double calibration_ms = 0;
  double t_eval = 0, t_skip = 0;  ///< seconds per VPL sample with / without the shadow ray
  bool calibrated = false;        ///< t_eval, t_skip measured by calibrate() (else given or unset)
  double preprocess_ms() const { return vpl_ms + shading_points_ms + cluster_ms + visibility_ms + pmf_ms; }
};

/// Per-sample costs, seconds.
struct SampleCosts {
  double t_eval = 0, t_skip = 0;
};

/// t_eval and t_skip from the calibration renders (sec. 5): the q = 0 pass took eval_pass_s
/// and the q = 1 pass skip_pass_s over `samples` samples, `contributing` of which have t > 0.
/// Only those trace a ray, so t_skip = skip_pass_s / samples and the others are charged
/// t_skip in the q = 0 pass (the cost model of eq. 11). A ray measured as costing nothing
/// (timing noise, or no contributing sample) gives t_eval = t_skip: skipping saves nothing.
SampleCosts calibrated_costs(double eval_pass_s, double skip_pass_s, double samples, double contributing);

/// When calibration measured t_eval <= t_skip, t_hat of eq. (16) is 0 and `mode` traces every
/// sample as exact does: the warning that says so; "" otherwise (exact, given costs, or a
/// shadow ray that costs time).
std::string skipping_saves_nothing_warning(VisibilityMode mode, const ManylightTimings& timings);

/// One point of an RMSE-over-time curve.
struct ProgressRecord {
  double seconds = 0;    ///< rendering time since the first pass (preprocess excluded)
  size_t passes = 0;
  double rmse = -1;      ///< against the reference; -1 without one
  double skip_rate = 0;  ///< fraction of VPL samples whose shadow ray was skipped so far
};

/// Renders eq. (6) progressively: every pass draws config.samples_per_pass VPL samples at
/// every shading point. Shading clusters are processed in wavefront rounds of
/// config.points_per_round points each; a round's shadow rays form one batch to
/// Accelerator::occluded, and t_hat, sigma^2 (eqs. 16, 17) of a cluster come from its
/// samples of earlier rounds (the first round of the first pass uses q = 0).
/// Holds references to scene and accel: both must outlive the renderer.
class ManylightRenderer {
 public:
  /// Runs the preprocess: VPLs, shading points, VisibilityCluster. No calibration yet.
  ManylightRenderer(const Scene& scene, const Accelerator& accel, const ManylightConfig& config);

  /// Measures t_eval and t_skip by low-resolution renders (every calibration_stride-th pixel
  /// row and column) with q = 0 and q = 1 (calibrated_costs), unless config gave both. Leaves
  /// the image empty.
  void calibrate();
  /// Switches the visibility mode and clears the image and statistics (preprocess is kept).
  void reset(VisibilityMode mode);
  /// Reseeds the per-pass randomness (independent renders over the same preprocess).
  void set_seed(uint64_t seed) { seed_ = seed; }

  /// One pass over every shading point; a skipping mode calibrates first if that is not done.
  void render_pass();
  /// Passes until `seconds` of rendering have elapsed (at least one, at most max_passes),
  /// recording the RMSE against `reference` (compare_images; an empty Image = none) after each
  /// pass, and handing each record to `on_pass` (if set) as it is made.
  std::vector<ProgressRecord> render_for(double seconds, const Image& reference,
                                         size_t max_passes = SIZE_MAX,
                                         const std::function<void(const ProgressRecord&)>& on_pass = {});

  /// Current estimate, width x height RGB (negative values possible, sec. 4.3).
  Image image() const;
  /// Per pixel fraction of skipped shadow rays so far (the paper's Fig. 3).
  std::vector<float> skip_image() const;
  double skip_rate() const;
  size_t passes() const { return passes_; }
  uint64_t shadow_rays_traced() const { return rays_traced_; }

  const ManylightConfig& config() const { return config_; }
  const ManylightTimings& timings() const { return timings_; }
  const VplSet& vpls() const { return vpls_; }
  const std::vector<ShadingPoint>& shading_points() const { return points_; }
  const VisibilityClusters& clusters() const { return clusters_; }
  /// Per shading cluster, the running sums of its samples so far that eqs. (16), (17) read.
  const std::vector<ClusterSampleStats>& cluster_stats() const { return stats_; }

 private:
  struct Sample;
  /// Seconds on config.cpu_clock's clock.
  double now() const;
  /// The config gives both costs; one alone is not used (both are calibrated then).
  bool costs_given() const { return config_.t_eval > 0 && config_.t_skip > 0; }
  enum class Forced { None, Zero, One };
  /// Per shading cluster, its points on every calibration_stride-th pixel row and column.
  std::vector<std::vector<uint32_t>> calibration_subset() const;
  /// One pass over the given shading clusters' point lists; forced q overrides (calibration).
  /// Returns the number of samples with a non-zero tentative contribution.
  size_t pass(const std::vector<std::vector<uint32_t>>& cluster_points, Forced forced, bool accumulate);
  /// Phase A of a round for one sample (VPL, contribution, skip coin); see the .cpp.
  void draw_sample(size_t cluster, uint32_t point, int j, Forced forced, Sample& sample, Ray& ray) const;
  /// Phase B of a round for one shading cluster's samples (eqs. (6), (8), statistics).
  void resolve_samples(size_t cluster, std::span<const Sample> samples, const std::vector<uint8_t>& occluded,
                       bool accumulate);

  const Scene& scene_;
  const Accelerator& accel_;
  ManylightConfig config_;
  ManylightTimings timings_;
  VplSet vpls_;
  std::vector<ShadingPoint> points_;
  VisibilityClusters clusters_;
  std::vector<std::vector<uint32_t>> cluster_points_;  ///< per shading cluster, processing order
  float offset_ = 1e-4f;

  std::vector<ClusterSampleStats> stats_;  ///< per shading cluster, eqs. (16), (17)
  /// Per shading point, the sum of per-pass estimates; double, as a reference adds thousands of passes.
  std::vector<std::array<double, 3>> point_sum_;
  std::vector<uint32_t> point_skipped_, point_samples_;
  size_t passes_ = 0;
  uint64_t rays_traced_ = 0;
  uint64_t seed_ = 1;
};

}  // namespace rayscout
