// Skip probability (eq. 15) against hand-computed values; the estimator of eq. (8) is unbiased.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "rayscout/manylight/probabilistic_visibility.h"

namespace rayscout {
namespace {

TEST(ManylightSkipProbability, ProposedMatchesHandComputedValue) {
  // t = 2, p = 0.5, r = 0.8: D = max(0.1, 0.8 * 0.2) = 0.16; t_hat = 1 / (1 - 0.2) - 0.25 = 1.
  // q = 1 - sqrt(4 * 0.16 / 0.25 * 1 / 16) = 1 - sqrt(0.16) = 0.6.
  const double th = t_hat(1.0, 0.2, 0.25);
  EXPECT_DOUBLE_EQ(th, 1.0);
  EXPECT_NEAR(skip_probability(VisibilityMode::Proposed, 2.0, 0.5, 0.8, th, 16.0, 0.1), 0.6, 1e-12);
}

TEST(ManylightSkipProbability, EpsilonFloorAppliesNearZeroAndOne) {
  // r = 1: r(1 - r) = 0 -> D = eps = 0.1; sqrt(1 * 0.1 / 1 * 2.5 / 1) = 0.5 -> q = 0.5.
  EXPECT_NEAR(skip_probability(VisibilityMode::Proposed, 1.0, 1.0, 1.0, 2.5, 1.0, 0.1), 0.5, 1e-12);
  EXPECT_NEAR(skip_probability(VisibilityMode::Proposed, 1.0, 1.0, 0.0, 2.5, 1.0, 0.1), 0.5, 1e-12);
  // Without the floor the skip would be certain (the bias of sec. 4.2).
  EXPECT_DOUBLE_EQ(skip_probability(VisibilityMode::Proposed, 1.0, 1.0, 1.0, 2.5, 1.0, 0.0), 1.0);
}

TEST(ManylightSkipProbability, VeachAndConservative) {
  // Veach: D = 1 whatever r: q = 1 - sqrt(0.25 * 1 / 1 * 1 / 4) = 0.75 (sigma^2 = 4).
  EXPECT_NEAR(skip_probability(VisibilityMode::Veach, 0.5, 1.0, 0.9, 1.0, 4.0, 0.1), 0.75, 1e-12);
  // Conservative, r = 0.9: D = max(0.01, 0.81) = 0.81: q = 1 - sqrt(0.81 / 4) = 0.55.
  EXPECT_NEAR(skip_probability(VisibilityMode::Conservative, 1.0, 1.0, 0.9, 1.0, 4.0, 0.1), 0.55, 1e-12);
  EXPECT_DOUBLE_EQ(visibility_error_bound(VisibilityMode::Conservative, 0.5, 0.1), 0.25);
  EXPECT_DOUBLE_EQ(visibility_prediction(VisibilityMode::Veach, 0.9), 0.0);
  EXPECT_DOUBLE_EQ(visibility_prediction(VisibilityMode::Proposed, 0.9), 0.9);
}

TEST(ManylightSkipProbability, ClampsAndDegenerateInputs) {
  EXPECT_DOUBLE_EQ(skip_probability(VisibilityMode::Exact, 1, 1, 0.5, 1, 1, 0.1), 0.0);
  // Large contribution: negative q clamps to 0.
  EXPECT_DOUBLE_EQ(skip_probability(VisibilityMode::Proposed, 100, 0.01, 0.5, 1, 1, 0.1), 0.0);
  // No statistics yet (sigma^2 = 0) or nothing to gain (t_hat = 0): always trace.
  EXPECT_DOUBLE_EQ(skip_probability(VisibilityMode::Proposed, 1, 1, 0.5, 1, 0, 0.1), 0.0);
  EXPECT_DOUBLE_EQ(skip_probability(VisibilityMode::Proposed, 1, 1, 0.5, 0, 1, 0.1), 0.0);
  EXPECT_DOUBLE_EQ(t_hat(1.0, 1.0, 0.0), 0.0);
  // Zero contribution: skipping is exact, q = 1.
  EXPECT_DOUBLE_EQ(skip_probability(VisibilityMode::Proposed, 0, 1, 0.5, 1, 1, 0.1), 1.0);
}

// A q just below 1 must leave the shadow ray a chance: q was once stored as float, so every
// double q above 1 - 2^-25 became 1.0f and such samples were never traced (eq. 8 needs 1 - q > 0).
TEST(ManylightSkipCoin, QJustBelowOneStaysTraceable) {
  // s = 1e-9 in eq. (15): q = 1 - 1e-9 in exact arithmetic, float(q) == 1.
  const double q = skip_probability(VisibilityMode::Veach, 1e-9, 1.0, 0.0, 1.0, 1.0, 0.1);
  ASSERT_EQ(float(1.0 - 1e-9), 1.0f);
  EXPECT_LT(q, 1.0);
  EXPECT_GE(1.0 - q, 0x1p-24);
  EXPECT_FALSE(skip_coin(q, ~uint64_t(0))) << "the largest random number must trace";
  // Proposed with eps > 0 and r = 1 likewise (D = eps > 0).
  const double qp = skip_probability(VisibilityMode::Proposed, 1e-9, 1.0, 1.0, 1.0, 1.0, 0.1);
  EXPECT_LT(qp, 1.0);
  EXPECT_FALSE(skip_coin(qp, ~uint64_t(0)));
  // Exact skips keep q = 1: zero contribution, and D = 0 (proposed, eps = 0, r = 1).
  EXPECT_EQ(skip_probability(VisibilityMode::Proposed, 0.0, 1.0, 0.5, 1.0, 1.0, 0.1), 1.0);
  EXPECT_EQ(skip_probability(VisibilityMode::Proposed, 1e-9, 1.0, 1.0, 1.0, 1.0, 0.0), 1.0);
  EXPECT_TRUE(skip_coin(1.0, ~uint64_t(0)));
}

// The coin skips for exactly the integers m < q 2^53 of the 53-bit m it draws, so
// P(skip) = q, the value eq. (8)'s weights use. A float q against a 24-bit u skipped with
// probability ceil(q 2^24) / 2^24 instead (up to 2^-24 more).
TEST(ManylightSkipCoin, SkipProbabilityIsExactlyTheWeightsQ) {
  for (double t : {0.3, 1.0 / 3.0, 0.01, 0.7654321, 1e-6, 1.5, 1.9}) {
    const double q = skip_probability(VisibilityMode::Proposed, t, 1.0, 0.5, 1.0, 1.0, 0.1);
    ASSERT_GT(q, 0.0);
    ASSERT_LT(q, 1.0);
    EXPECT_EQ(skip_coin_probability(q), q) << "q is on the coin's grid";
    const uint64_t threshold = uint64_t(std::ldexp(q, 53));  // exact: q is a multiple of 2^-53
    EXPECT_EQ(std::ldexp(double(threshold), -53), q);
    EXPECT_TRUE(skip_coin(q, (threshold - 1) << 11)) << "t = " << t;
    EXPECT_FALSE(skip_coin(q, threshold << 11)) << "t = " << t;
  }
  // Rounding an off-grid q up to the grid moves it by less than 2^-53.
  const double q = 0.1234567890123456789;
  EXPECT_GE(skip_coin_probability(q), q);
  EXPECT_LT(skip_coin_probability(q) - q, 0x1p-53);
  EXPECT_FALSE(skip_coin(0.0, 0));
}

TEST(ManylightSkipCoin, EpsilonZeroWithProposedIsWarnedAbout) {
  EXPECT_NE(epsilon_bias_warning(VisibilityMode::Proposed, 0.0), "");
  EXPECT_EQ(epsilon_bias_warning(VisibilityMode::Proposed, 0.1), "");
  EXPECT_EQ(epsilon_bias_warning(VisibilityMode::Veach, 0.0), "");
  EXPECT_EQ(epsilon_bias_warning(VisibilityMode::Conservative, 0.0), "");
}

TEST(ManylightVisibilityEstimate, TracedValueMatchesEq8) {
  EXPECT_DOUBLE_EQ(visibility_estimate(false, 1.0, 0.8, 0.5), (1.0 - 0.4) / 0.5);
  EXPECT_DOUBLE_EQ(visibility_estimate(false, 0.0, 0.8, 0.5), -0.8);
  EXPECT_DOUBLE_EQ(visibility_estimate(true, 0.0, 0.8, 0.5), 0.8);
  // q = 0 is exact visibility.
  EXPECT_DOUBLE_EQ(visibility_estimate(false, 1.0, 0.3, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(visibility_estimate(false, 0.0, 0.3, 0.0), 0.0);
}

TEST(ManylightVisibilityEstimate, ExpectationIsTheTrueVisibilityAndVarianceIsEq9) {
  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (double v : {0.0, 1.0})
    for (double r : {0.0, 0.3, 1.0})
      for (double q : {0.2, 0.7, 0.95}) {
        const int n = 200000;
        double sum = 0, sum2 = 0;
        for (int i = 0; i < n; ++i) {
          const double x = visibility_estimate(u(gen) < q, v, r, q);
          sum += x;
          sum2 += x * x;
        }
        const double mean = sum / n, var = sum2 / n - mean * mean;
        const double expected_var = q * (v - r) * (v - r) / (1 - q);  // eq. (9)
        const double se = std::sqrt(std::max(expected_var, 1e-12) / n);
        EXPECT_NEAR(mean, v, 4 * se + 1e-12) << "v=" << v << " r=" << r << " q=" << q;
        EXPECT_NEAR(var, expected_var, 0.05 * expected_var + 1e-9) << "v=" << v << " r=" << r << " q=" << q;
      }
}

TEST(ManylightClusterSampleStats, MeansAndEq17Variance) {
  ClusterSampleStats st;
  EXPECT_DOUBLE_EQ(st.variance(), 0.0);
  st.add(0.5, 1.0);
  EXPECT_DOUBLE_EQ(st.variance(), 0.0);
  st.add(0.0, 3.0);
  st.add(1.0, 5.0);
  EXPECT_DOUBLE_EQ(st.mean_q(), 0.5);
  EXPECT_NEAR(st.variance(), 8.0 / 3.0, 1e-12);  // 1/N sum (y - 3)^2 = (4 + 0 + 4) / 3
}

// Eq. (15) with t_hat (eq. 16) and sigma2 (eq. 17) taken from a cluster's earlier samples, as
// the renderer calls it. Passing sigma2 for t_hat and t_hat for sigma2, or leaving out the mean
// q of eq. (16), keeps the estimator unbiased (only q changes) and passed every other test.
TEST(ManylightSkipProbability, FromTheClustersEarlierSamples) {
  ClusterSampleStats earlier;
  earlier.add(0.0, 0.0);
  earlier.add(0.5, 4.0);
  // mean q = 0.25, sigma2 = (0 + 16) / 2 - 2^2 = 4; t_hat = 1 / (1 - 0.2) - 0.25 = 1.
  // t = 2, p = 0.5, r = 0.8: D = 0.16, q = 1 - sqrt(4 * 0.16 / 0.25 * 1 / 4) = 1 - 0.8 = 0.2.
  EXPECT_NEAR(skip_probability(VisibilityMode::Proposed, 2.0, 0.5, 0.8, earlier, 1.0, 0.2, 0.1), 0.2, 1e-12);
  // Nothing known yet (sigma2 = 0 before two samples): trace.
  ClusterSampleStats one;
  one.add(0.0, 4.0);
  EXPECT_EQ(skip_probability(VisibilityMode::Proposed, 2.0, 0.5, 0.8, one, 1.0, 0.2, 0.1), 0.0);
}

}  // namespace
}  // namespace rayscout
