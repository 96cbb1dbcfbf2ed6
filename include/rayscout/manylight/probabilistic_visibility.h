// Probabilistic visibility (Nabata & Iwasaki 2019): skip probability and visibility estimate.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "rayscout/manylight/manylight_config.h"

namespace rayscout {

/// The squared visibility error (v_i - r_i)^2 as each mode replaces it in eq. (15).
inline double visibility_error_bound(VisibilityMode mode, double r, double epsilon) {
  switch (mode) {
    case VisibilityMode::Exact: return 1.0;  // unused: q = 0
    case VisibilityMode::Veach: return 1.0;  // r = 0, (v - 0)^2 <= 1
    case VisibilityMode::Conservative: return std::max((1.0 - r) * (1.0 - r), r * r);
    case VisibilityMode::Proposed: return std::max(epsilon, r * (1.0 - r));
  }
  return 1.0;
}

/// The prediction r_i each mode uses in eq. (8): 0 for Veach, the cluster average otherwise.
inline double visibility_prediction(VisibilityMode mode, double r) {
  return mode == VisibilityMode::Veach ? 0.0 : r;
}

/// t_hat of eq. (16): t_eval / t_diff - mean(q) over earlier samples; 0 when skipping saves nothing.
inline double t_hat(double t_eval, double t_skip, double mean_q) {
  const double t_diff = t_eval - t_skip;
  if (!(t_diff > 0.0)) return 0.0;
  return t_eval / t_diff - mean_q;
}

/// The skip coin compares 53 random bits, an integer m uniform in [0, 2^53), with q 2^53, so it
/// skips with probability exactly q when q is a multiple of 2^-53 (every q in [0.5, 1] is).
inline constexpr int kSkipCoinBits = 53;
/// Largest q of a sample whose skip is not exact (t D > 0): the shadow ray keeps a trace
/// probability of at least 2^-24, so V~ of eq. (8) stays unbiased; the cap costs nothing
/// measurable (q is only this large when t is negligible against sigma, eq. 15).
inline constexpr double kMaxInexactSkipProbability = 1.0 - 0x1p-24;

/// q rounded up to the coin's 2^-53 grid: the probability with which skip_coin() skips, and
/// therefore the q that eq. (8)'s weights must use. (1 - s of eq. 15 is on that grid already,
/// by Sterbenz' lemma; the rounding keeps the contract for any other q.)
inline double skip_coin_probability(double q) {
  return std::ldexp(std::ceil(std::ldexp(q, kSkipCoinBits)), -kSkipCoinBits);
}

/// The coin of eq. (8): true (skip) with probability skip_coin_probability(q), from 64 uniform
/// random bits (their top 53 are used).
inline bool skip_coin(double q, uint64_t random_bits) {
  const uint64_t m = random_bits >> (64 - kSkipCoinBits);
  return m < uint64_t(std::ldexp(skip_coin_probability(q), kSkipCoinBits));
}

/// Skip probability q_i of eq. (15): 1 - sqrt(t^2 D / p^2 * t_hat / sigma2), clamped to
/// [0, kMaxInexactSkipProbability] and put on the coin's grid, so skip_coin(q) skips with
/// probability exactly q. t = scalar tentative contribution, p = pmf of the sample, D = the
/// mode's (v - r)^2 replacement, sigma2 = eq. (17). q = 0 when nothing is known yet
/// (sigma2 <= 0) or skipping saves nothing (t_hat <= 0); q = 1 only when t * D = 0: exact
/// for t = 0, and for D = 0 (proposed with eps = 0 and r in {0, 1}) the bias that sec. 4.2's
/// eps > 0 avoids (see epsilon_bias_warning).
inline double skip_probability(VisibilityMode mode, double t, double p, double r, double t_hat_value,
                               double sigma2, double epsilon) {
  if (mode == VisibilityMode::Exact) return 0.0;
  if (!(sigma2 > 0.0) || !(t_hat_value > 0.0) || !(p > 0.0)) return 0.0;
  const double d = visibility_error_bound(mode, r, epsilon);
  if (!(t > 0.0) || !(d > 0.0)) return 1.0;
  const double s = std::sqrt(t * t * d / (p * p) * t_hat_value / sigma2);
  return skip_coin_probability(std::clamp(1.0 - s, 0.0, kMaxInexactSkipProbability));
}

/// Sec. 4.2: with eps = 0, `proposed` skips every sample whose r is 0 or 1 with q = 1, and
/// where that prediction is wrong the estimate does not converge to eq. (1). The warning to
/// print for such a configuration; "" otherwise.
inline std::string epsilon_bias_warning(VisibilityMode mode, double epsilon) {
  if (mode != VisibilityMode::Proposed || epsilon > 0.0) return "";
  return "--epsilon 0 with --visibility proposed is biased: samples whose cluster visibility r is 0 or 1 are never "
         "traced, so where r is wrong the image does not converge (Nabata & Iwasaki 2019, sec. 4.2; eps = 0.1 is the "
         "paper's value)";
}

/// The estimate V~ of eq. (8): r when skipped; (v - r q) / (1 - q) when traced. skipped must be
/// false when q = 0.
inline double visibility_estimate(bool skipped, double v, double r, double q) {
  return skipped ? r : (v - r * q) / (1.0 - q);
}

/// Running sums of one shading cluster's earlier samples for eqs. (16) and (17).
struct ClusterSampleStats {
  double n = 0, sum_q = 0, sum_y = 0, sum_y2 = 0;  ///< y = scalar t V~ / p

  void add(double q, double y) { n += 1; sum_q += q; sum_y += y; sum_y2 += y * y; }
  double mean_q() const { return n > 0 ? sum_q / n : 0.0; }
  /// Eq. (17): the (biased, 1/N) sample variance of y; 0 before two samples.
  double variance() const {
    if (n < 2) return 0.0;
    const double m = sum_y / n;
    return std::max(0.0, sum_y2 / n - m * m);
  }
};

/// Eq. (15) for a sample of a shading cluster whose earlier samples are `earlier` (sec. 4.1):
/// t_hat of eq. (16) from the costs (seconds per sample) and their mean q, sigma2 = eq. (17).
/// t is the scalar tentative contribution, not t / p (eq. 15 divides by p itself).
inline double skip_probability(VisibilityMode mode, double t, double p, double r, const ClusterSampleStats& earlier,
                               double t_eval, double t_skip, double epsilon) {
  return skip_probability(mode, t, p, r, t_hat(t_eval, t_skip, earlier.mean_q()), earlier.variance(), epsilon);
}

}  // namespace rayscout
