// DiscreteDistribution: the probability reported is the length of the range that chooses.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "rayscout/core/discrete_distribution.h"

namespace rayscout {
namespace {

TEST(DiscreteDistribution, RangesAreTheProbabilities) {
  const std::vector<double> w{1e-30, 3.0, 0.0, 1.0, 1e-7};
  for (int bits : {8, 24, 53}) {
    const DiscreteDistribution d(w, bits);
    ASSERT_EQ(d.size(), w.size());
    EXPECT_EQ(d.cdf(w.size() - 1), uint64_t(1) << bits);
    double sum = 0;
    for (size_t k = 0; k < w.size(); ++k) {
      const uint64_t lo = k ? d.cdf(k - 1) : 0, hi = d.cdf(k);
      EXPECT_EQ(d.probability(k), std::ldexp(double(hi - lo), -bits)) << bits << " " << k;
      sum += d.probability(k);
      if (w[k] == 0) { EXPECT_EQ(hi, lo); continue; }
      ASSERT_GT(hi, lo) << "a positive weight keeps a step: " << bits << " " << k;
      EXPECT_EQ(d.sample(lo), k);
      EXPECT_EQ(d.sample(hi - 1), k);
      // Rounding and the one-unit floor move each share by at most a unit; the largest one takes
      // up the others' rounding.
      EXPECT_LE(std::fabs(d.probability(k) - w[k] / (4.0 + 1e-7 + 1e-30)), std::ldexp(double(w.size()), -bits)) << k;
    }
    EXPECT_EQ(sum, 1.0);
    EXPECT_EQ(d.sample_bits(~uint64_t(0)), w.size() - 1);
    EXPECT_EQ(d.sample_bits(0), 0u);
  }
}

// Many items whose one-unit floors outweigh the largest item's units (half of 256 items tiny on
// 2^10 units: 128 floors against 8 units), and finite weights whose sum overflows double: both
// are valid weights, which threw "too uneven to quantise" and "no positive weight".
TEST(DiscreteDistribution, ManyTinyItemsAndHugeWeights) {
  std::vector<double> w(128, 1.0);
  w.resize(256, 1e-9);
  const DiscreteDistribution many(w, 10);
  EXPECT_EQ(many.cdf(w.size() - 1), uint64_t(1) << 10);
  for (size_t k = 0; k < w.size(); ++k) EXPECT_GE(many.probability(k), std::ldexp(1.0, -10)) << k;

  const std::vector<double> huge{1e308, 1e308, 0.0, 1e-300};
  const DiscreteDistribution d(huge, 53);
  EXPECT_EQ(d.probability(0), 0.5 - std::ldexp(1.0, -53));  // the largest gives the floor's unit
  EXPECT_EQ(d.probability(1), 0.5);
  EXPECT_EQ(d.probability(2), 0.0);
  EXPECT_EQ(d.probability(3), std::ldexp(1.0, -53));
}

// m beyond 2^bits is clamped to the last unit, which an item of weight 0 never owns (the last
// item was returned whatever its weight).
TEST(DiscreteDistribution, ClampedSampleNeverChoosesWeightZero) {
  const DiscreteDistribution d(std::vector<double>{1.0, 0.0}, 8);
  EXPECT_EQ(d.sample(255), 0u);
  EXPECT_EQ(d.sample(256), 0u);
  EXPECT_EQ(d.sample(~uint64_t(0)), 0u);
}

TEST(DiscreteDistribution, RejectsBadWeights) {
  EXPECT_THROW(DiscreteDistribution(std::vector<double>{0.0, 0.0}, 24), std::invalid_argument);
  EXPECT_THROW(DiscreteDistribution(std::vector<double>{1.0, -1.0}, 24), std::invalid_argument);
  EXPECT_THROW(DiscreteDistribution(std::vector<double>{1.0, NAN}, 24), std::invalid_argument);
  EXPECT_THROW(DiscreteDistribution(std::vector<double>{1.0, INFINITY}, 24), std::invalid_argument);
  EXPECT_THROW(DiscreteDistribution(std::vector<double>{}, 24), std::invalid_argument);
  EXPECT_THROW(DiscreteDistribution(std::vector<double>(5, 1.0), 4), std::invalid_argument);
  EXPECT_THROW(DiscreteDistribution(std::vector<double>{1.0}, 54), std::invalid_argument);
}

}  // namespace
}  // namespace rayscout
