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

// sample_bits reads exactly the top `bits` bits: an off-by-one shift still passes all-zero and
// all-one bits, but not the two halves' boundary.
TEST(DiscreteDistribution, SampleBitsReadsTheTopBits) {
  for (int bits : {3, 24, 53}) {
    const DiscreteDistribution d(std::vector<double>{1.0, 1.0}, bits);
    EXPECT_EQ(d.sample_bits((uint64_t(1) << 63) - 1), 0u) << bits;
    EXPECT_EQ(d.sample_bits(uint64_t(1) << 63), 1u) << bits;
  }
}

// Each share is rounded to the nearest unit: an item that neither is the largest nor gets the
// one-unit floor is within half a unit of weight / total.
TEST(DiscreteDistribution, SharesAreRoundedToTheNearestUnit) {
  const std::vector<double> w{10.0, 2.9, 1.6, 0.7, 3.3};  // 2.9 / 18.5 * 256 = 40.13, 0.7 -> 9.69
  const DiscreteDistribution d(w, 8);
  for (size_t k = 1; k < w.size(); ++k)
    EXPECT_LE(std::fabs(d.probability(k) * 256 - w[k] / 18.5 * 256), 0.5) << k;
}

// When the one-unit floors of tiny items outweigh what the largest item can give, the next
// largest give up units (largest count first), so lighter items keep their rounded share.
TEST(DiscreteDistribution, LargestItemsAbsorbTheFloors) {
  std::vector<double> w{2, 2, 2, 2, 1, 1, 1, 1};  // 43 units each for 2, 21 for 1: 256 in all
  w.resize(64, 1e-12);                            // 56 floors of one unit to pay for
  const DiscreteDistribution d(w, 8);
  const auto units = [&](size_t k) { return d.cdf(k) - (k ? d.cdf(k - 1) : 0); };
  EXPECT_EQ(units(0), 1u);   // gives 42 of the 56
  EXPECT_EQ(units(1), 29u);  // the next largest gives the other 14
  EXPECT_EQ(units(2), 43u);
  EXPECT_EQ(units(3), 43u);
  for (size_t k = 4; k < 8; ++k) EXPECT_EQ(units(k), 21u) << k;
  for (size_t k = 8; k < w.size(); ++k) EXPECT_EQ(units(k), 1u) << k;
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

namespace rayscout {
namespace {

// The rounding remainder goes to the largest item (the first of equal ones), where it changes
// the share least: the smallest absorbing it passed the other tests (their shares round to
// exactly 2^bits, or they skip item 0).
TEST(DiscreteDistribution, TheLargestItemAbsorbsTheRoundingRemainder) {
  const auto units = [](const DiscreteDistribution& d, size_t k) { return d.cdf(k) - (k ? d.cdf(k - 1) : 0); };
  const DiscreteDistribution short_of(std::vector<double>{3, 5, 7}, 4);  // 3.2, 5.33, 7.47 -> 3 + 5 + 7 = 15
  EXPECT_EQ(units(short_of, 0), 3u);
  EXPECT_EQ(units(short_of, 1), 5u);
  EXPECT_EQ(units(short_of, 2), 8u);
  const DiscreteDistribution over(std::vector<double>{1, 2.6, 2.6}, 4);  // 2.58, 6.71, 6.71 -> 3 + 7 + 7 = 17
  EXPECT_EQ(units(over, 0), 3u);
  EXPECT_EQ(units(over, 1), 6u);
  EXPECT_EQ(units(over, 2), 7u);
}

}  // namespace
}  // namespace rayscout
