// ManylightRenderer: wavefront rounds over shading clusters with probabilistic visibility.
#include "rayscout/manylight/manylight_renderer.h"

#include <algorithm>
#include <cmath>
#include <span>
#include <string>

#include <fmt/core.h>
#include <tbb/parallel_for.h>

#include "rayscout/core/input_error.h"
#include "rayscout/core/stopwatch.h"
#include "rayscout/manylight/channel_mean.h"
#include "ray_offset.h"
#include "rng.h"

namespace rayscout {

double ManylightRenderer::now() const {
  return (config_.cpu_clock ? process_cpu_ms() : wall_ms()) * 1e-3;
}

namespace {
/// What became of one slot of a round's sample buffer.
enum class SampleState : uint8_t {
  Empty,             ///< no point in this slot this round
  ZeroContribution,  ///< t = 0: V~ is irrelevant, no ray (exact, not a skip)
  Skipped,           ///< the coin skipped: V~ = r (eq. 8)
  Traced,            ///< the shadow ray is in the round's batch: V~ = (v - r q) / (1 - q)
};
}  // namespace

/// One VPL sample in a round's buffer.
struct ManylightRenderer::Sample {
  Vec3 t_over_p;             // per colour; the estimate of eq. (6) is t_over_p V~
  float scalar_t_over_p = 0; // channel_mean(t_over_p): y = scalar_t_over_p V~ in eq. (17)
  float r = 0;
  double q = 0;       // the skip coin's probability, exactly as eq. (8)'s weights use it
  uint32_t point = 0;
  uint32_t ray = 0;   // index into the round's ray batch when traced
  SampleState state = SampleState::Empty;
};

namespace {
/// Throws InputError for a config the renderer cannot use, or not without bias.
void check_config(const ManylightConfig& config) {
  if (config.samples_per_pass <= 0 || config.points_per_round <= 0)
    throw InputError("manylight: samples_per_pass and points_per_round must be positive");
  if (!(config.epsilon >= 0.0f)) throw InputError("manylight: epsilon must be >= 0");
  // Without the uniform mix a VPL cluster whose estimated contribution is 0 would never be
  // drawn, and its light would be missing from the image (biased).
  if (!(config.uniform_mix > 0.0f && config.uniform_mix <= 1.0f))
    throw InputError("manylight: uniform_mix must be in (0, 1], got " + std::to_string(config.uniform_mix));
  if (config.visibility_samples < 1 || config.visibility_samples > kMaxPairSamples ||
      config.refine_samples < 0 || config.refine_samples > kMaxPairSamples ||
      config.contribution_samples < 0 || config.contribution_samples > kMaxPairSamples)
    throw InputError("manylight: visibility_samples must be in [1, " + std::to_string(kMaxPairSamples) +
                     "], refine_samples and contribution_samples in [0, " + std::to_string(kMaxPairSamples) + "]");
  if (!(config.r_floor >= 0.0f && config.r_floor <= 1.0f))
    throw InputError("manylight: r_floor must be in [0, 1], got " + std::to_string(config.r_floor));
}

/// Per shading cluster, its points in pixel order: neighbours follow each other (sec. 4.1).
std::vector<std::vector<uint32_t>> processing_order(const Clustering& shading) {
  std::vector<std::vector<uint32_t>> lists(shading.size());
  for (size_t c = 0; c < lists.size(); ++c) {
    lists[c].assign(shading.order.begin() + shading.begin[c], shading.order.begin() + shading.begin[c + 1]);
    std::sort(lists[c].begin(), lists[c].end());
  }
  return lists;
}
}  // namespace

ManylightRenderer::ManylightRenderer(const Scene& scene, const Accelerator& accel, const ManylightConfig& config)
    : scene_(scene), accel_(accel), config_(config), seed_(config.seed) {
  check_config(config_);
  offset_ = manylight_detail::ray_offset(scene);
  // Preprocess times on the configured clock; the split of VisibilityCluster into its
  // phases is wall-clock, scaled to the measured total.
  double t0 = now();
  vpls_ = generate_vpls(scene, accel, config_);
  timings_.vpl_ms = (now() - t0) * 1e3;
  t0 = now();
  points_ = generate_shading_points(scene, accel, config_);
  timings_.shading_points_ms = (now() - t0) * 1e3;
  if (vpls_.vpls.empty())
    throw InputError("manylight: the scene has no light that emits (a point light with intensity > 0 or an "
                     "emissive triangle)");
  t0 = now();
  clusters_ = build_visibility_clusters(scene, accel, points_, vpls_, config_);
  const double total_ms = (now() - t0) * 1e3;
  const double wall = clusters_.cluster_ms + clusters_.visibility_ms + clusters_.pmf_ms;
  const double scale = wall > 0 ? total_ms / wall : 1.0;
  timings_.cluster_ms = clusters_.cluster_ms * scale;
  timings_.visibility_ms = clusters_.visibility_ms * scale;
  timings_.pmf_ms = clusters_.pmf_ms * scale;
  cluster_points_ = processing_order(clusters_.shading);
  if (costs_given()) {
    timings_.t_eval = config_.t_eval;
    timings_.t_skip = config_.t_skip;
  }
  reset(config_.mode);
}

void ManylightRenderer::reset(VisibilityMode mode) {
  config_.mode = mode;
  stats_.assign(cluster_points_.size(), {});
  point_sum_.assign(points_.size(), {0.0, 0.0, 0.0});
  point_skipped_.assign(points_.size(), 0);
  point_samples_.assign(points_.size(), 0);
  passes_ = 0;
  rays_traced_ = 0;
}

SampleCosts calibrated_costs(double eval_pass_s, double skip_pass_s, double samples, double contributing) {
  SampleCosts costs;
  costs.t_skip = skip_pass_s / samples;
  const double per_ray = contributing > 0 ? (eval_pass_s - (samples - contributing) * costs.t_skip) / contributing : 0;
  costs.t_eval = std::max(costs.t_skip, per_ray);
  return costs;
}

std::string skipping_saves_nothing_warning(VisibilityMode mode, const ManylightTimings& timings) {
  if (mode == VisibilityMode::Exact || !timings.calibrated || timings.t_eval > timings.t_skip) return "";
  return fmt::format("calibration measured no time for the shadow ray (t_eval = t_skip = {:.3g} us per sample): "
                     "skipping saves nothing (t_hat = 0 in eq. 16), so --visibility {} traces every sample as exact "
                     "does; --costs EVAL,SKIP sets the costs instead",
                     timings.t_skip * 1e6, to_string(mode));
}

std::vector<std::vector<uint32_t>> ManylightRenderer::calibration_subset() const {
  const int stride = std::max(1, config_.calibration_stride);
  std::vector<std::vector<uint32_t>> subset(cluster_points_.size());
  for (size_t c = 0; c < cluster_points_.size(); ++c)
    for (uint32_t p : cluster_points_[c]) {
      const uint32_t px = points_[p].pixel;
      if ((px % config_.width) % stride == 0 && (px / config_.width) % stride == 0) subset[c].push_back(p);
    }
  return subset;
}

void ManylightRenderer::calibrate() {
  if (costs_given()) return;
  const double t0 = now();
  const std::vector<std::vector<uint32_t>> subset = calibration_subset();
  size_t count = 0;
  for (const auto& s : subset) count += s.size();
  const double samples = double(std::max<size_t>(1, count)) * config_.samples_per_pass;
  double best_eval = INFINITY, best_skip = INFINITY;
  size_t contributing = 0;
  // Alternate and keep the minimum: the machine is shared, the minimum is the least disturbed.
  for (int rep = 0; rep < 3; ++rep) {
    double t = now();
    contributing = pass(subset, Forced::Zero, false);
    best_eval = std::min(best_eval, now() - t);
    t = now();
    pass(subset, Forced::One, false);
    best_skip = std::min(best_skip, now() - t);
  }
  const SampleCosts costs = calibrated_costs(best_eval, best_skip, samples, double(contributing));
  timings_.t_eval = costs.t_eval;
  timings_.t_skip = costs.t_skip;
  timings_.calibrated = true;
  timings_.calibration_ms = (now() - t0) * 1e3;
  reset(config_.mode);
}

void ManylightRenderer::render_pass() {
  if (config_.mode != VisibilityMode::Exact && !costs_given() && !timings_.calibrated) calibrate();
  pass(cluster_points_, Forced::None, true);
  ++passes_;
}

// Phase A for one sample: sample j of `point` (in shading cluster c) draws a VPL from the
// cluster's row, weighs its tentative contribution and tosses the skip coin with q from the
// cluster's samples of earlier rounds; a traced sample's shadow ray goes to `ray`.
void ManylightRenderer::draw_sample(size_t c, uint32_t point, int j, Forced forced, Sample& s, Ray& ray) const {
  const ShadingPoint& sp = points_[point];
  manylight_detail::Rng rng(seed_ + passes_ * kGolden64, manylight_detail::kRenderStream | point,
                            uint64_t(j) | (uint64_t(forced) << 32));
  s.point = point;
  // Sec. 3: a VPL cluster from the row, then a VPL uniformly in it: p = P(cluster) / |cluster|.
  const DiscreteDistribution& cluster_choice = clusters_.vpl_cluster_choice[c];
  const size_t vpl_cluster = cluster_choice.sample_bits(rng.bits64());
  const uint32_t members = clusters_.lights.count(vpl_cluster);
  const Vpl& vpl = vpls_.vpls[clusters_.lights.order[clusters_.lights.begin[vpl_cluster] + rng.below(members)]];
  const double p = cluster_choice.probability(vpl_cluster) / double(members);
  const Vec3 t = tentative_contribution(scene_, sp, vpl, config_.clamp_distance);
  if (max_component(t) <= 0.0f) {
    // No ray in any mode (exact, not a skip). Such a sample costs what a skipped one does
    // (calibrate() charges it t_skip), so it enters mean(q) of eq. (16) with q = 1, and
    // eq. (17) with y = t V~ / p = 0.
    s.state = SampleState::ZeroContribution;
    s.t_over_p = Vec3(0.0f);
    s.q = 1;
    s.r = 0;
    s.scalar_t_over_p = 0;
    return;
  }
  s.t_over_p = t * float(1.0 / p);
  s.scalar_t_over_p = channel_mean(s.t_over_p);
  s.r = float(visibility_prediction(config_.mode, clusters_.r[c * clusters_.vpl_cluster_count() + vpl_cluster]));
  double q = 0;
  if (forced == Forced::One) q = 1;
  else if (forced == Forced::None)
    q = skip_probability(config_.mode, channel_mean(t), p, s.r, stats_[c], timings_.t_eval, timings_.t_skip,
                         config_.epsilon);
  s.q = q;
  // skip_coin skips with probability exactly q (q is on its 2^-53 grid), and eq. (8) in
  // resolve_samples weights with the same double q.
  if (skip_coin(q, rng.bits64())) {
    s.state = SampleState::Skipped;
    return;
  }
  s.state = SampleState::Traced;
  ray = shadow_ray(sp, vpl, offset_);
}

namespace {
/// V~ of eq. (8) for a sample of a finished round: r when skipped, (v - r q) / (1 - q) when
/// traced; 0 for a zero contribution (it multiplies t = 0). A skipped sample's `ray` is stale.
double estimated_visibility(SampleState state, double r, double q, uint32_t ray, const std::vector<uint8_t>& occluded) {
  switch (state) {
    case SampleState::Skipped: return visibility_estimate(true, 0.0, r, q);
    case SampleState::Traced: return visibility_estimate(false, occluded[ray] ? 0.0 : 1.0, r, q);
    default: return 0.0;
  }
}
}  // namespace

// Phase B for the samples of one shading cluster: V~ of eq. (8), the pixel estimate of
// eq. (6), and the cluster statistics of eqs. (16) and (17).
void ManylightRenderer::resolve_samples(size_t c, std::span<const Sample> samples, const std::vector<uint8_t>& occluded,
                                        bool accumulate) {
  ClusterSampleStats& st = stats_[c];
  const int spp_samples = config_.samples_per_pass;
  for (const Sample& s : samples) {
    if (s.state == SampleState::Empty) continue;
    const double v_tilde = estimated_visibility(s.state, s.r, s.q, s.ray, occluded);
    st.add(s.q, s.scalar_t_over_p * v_tilde);  // a zero contribution adds q = 1, y = 0 (draw_sample)
    if (!accumulate) continue;
    for (int k = 0; k < 3; ++k) point_sum_[s.point][k] += double(s.t_over_p[k]) * v_tilde / spp_samples;
    if (s.state != SampleState::ZeroContribution) {
      point_samples_[s.point]++;
      point_skipped_[s.point] += s.state == SampleState::Skipped ? 1u : 0u;
    }
  }
}

size_t ManylightRenderer::pass(const std::vector<std::vector<uint32_t>>& cluster_points, Forced forced, bool accumulate) {
  const size_t nc = cluster_points.size();
  const size_t per_round = size_t(config_.points_per_round);
  const int spp_samples = config_.samples_per_pass;
  const size_t stride = per_round * spp_samples;
  size_t rounds = 0;
  for (const auto& l : cluster_points) rounds = std::max(rounds, (l.size() + per_round - 1) / per_round);
  std::vector<Sample> samples(nc * stride);
  std::vector<Ray> ray_of(nc * stride);
  RayBatch rays;
  std::vector<uint8_t> occluded;
  size_t contributing = 0;
  for (size_t round = 0; round < rounds; ++round) {
    // Phase A: sample VPLs and decide skips with the statistics of earlier rounds (stats_ is
    // only read here; phase B updates it).
    tbb::parallel_for(size_t(0), nc, [&](size_t c) {
      const auto& list = cluster_points[c];
      const size_t b = round * per_round, e = std::min(list.size(), b + per_round);
      for (size_t k = 0; k < stride; ++k) samples[c * stride + k].state = SampleState::Empty;
      for (size_t i = b; i < e; ++i)
        for (int j = 0; j < spp_samples; ++j) {
          const size_t k = c * stride + (i - b) * spp_samples + j;
          draw_sample(c, list[i], j, forced, samples[k], ray_of[k]);
        }
    });
    rays.clear();
    for (size_t k = 0; k < samples.size(); ++k) {
      const SampleState state = samples[k].state;
      contributing += state == SampleState::Skipped || state == SampleState::Traced ? 1 : 0;
      if (state == SampleState::Traced) { samples[k].ray = uint32_t(rays.size()); rays.push_back(ray_of[k]); }
    }
    if (!rays.empty()) accel_.occluded(rays, occluded);
    rays_traced_ += accumulate ? rays.size() : 0;
    // Phase B: V~ of eq. (8), the pixel estimate of eq. (6), and the cluster statistics.
    tbb::parallel_for(size_t(0), nc, [&](size_t c) {
      resolve_samples(c, std::span<const Sample>(samples).subspan(c * stride, stride), occluded, accumulate);
    });
  }
  return contributing;
}

std::vector<ProgressRecord> ManylightRenderer::render_for(double seconds, const Image& reference, size_t max_passes,
                                                         const std::function<void(const ProgressRecord&)>& on_pass) {
  std::vector<ProgressRecord> records;
  double elapsed = 0;
  while (passes_ < max_passes && (records.empty() || elapsed < seconds)) {
    const double t = now();
    render_pass();
    elapsed += now() - t;
    ProgressRecord rec;
    rec.seconds = elapsed;
    rec.passes = passes_;
    rec.skip_rate = skip_rate();
    if (!reference.pixels.empty()) rec.rmse = compare_images(image(), reference).rmse;
    records.push_back(rec);
    if (on_pass) on_pass(rec);
  }
  return records;
}

Image ManylightRenderer::image() const {
  Image img(config_.width, config_.height);
  const double inv = passes_ ? 1.0 / double(passes_) : 0.0;
  for (size_t p = 0; p < points_.size(); ++p) {
    const ShadingPoint& sp = points_[p];
    const std::array<double, 3>& sum = point_sum_[p];
    const Vec3 mean(float(sum[0] * inv), float(sum[1] * inv), float(sum[2] * inv));
    img.pixels[sp.pixel] += sp.emitted + sp.weight * mean;
  }
  return img;
}

std::vector<float> ManylightRenderer::skip_image() const {
  std::vector<float> skipped(size_t(config_.width) * config_.height, 0.0f), total(skipped.size(), 0.0f);
  for (size_t p = 0; p < points_.size(); ++p) {
    skipped[points_[p].pixel] += float(point_skipped_[p]);
    total[points_[p].pixel] += float(point_samples_[p]);
  }
  for (size_t i = 0; i < skipped.size(); ++i) skipped[i] = total[i] > 0 ? skipped[i] / total[i] : 0.0f;
  return skipped;
}

double ManylightRenderer::skip_rate() const {
  uint64_t skipped = 0, total = 0;
  for (size_t p = 0; p < points_.size(); ++p) { skipped += point_skipped_[p]; total += point_samples_[p]; }
  return total ? double(skipped) / double(total) : 0.0;
}

}  // namespace rayscout
