// DiscreteDistribution: choosing one of n items in proportion to weights, with the reported
// probability equal to the probability of the choice, however small it is.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace rayscout {

/// A choice among n items in proportion to non-negative weights, quantised to a grid of
/// 2^bits units (bits <= 53): item k owns the integer range [cdf(k - 1), cdf(k)) of a uniform
/// integer m in [0, 2^bits), so with m uniform it is chosen with probability exactly
/// (cdf(k) - cdf(k - 1)) / 2^bits = probability(k). A float CDF searched with a uniform u
/// does not have that property: where u's grid is coarser than the CDF's steps, the step and
/// the chance of the choice differ (a light of probability 1e-7 next to a bright one was
/// chosen 1.19 times as often as its weight said with u on a 2^-24 grid).
/// Each share weight / total is rounded to the nearest unit (2^-bits), and every item of
/// positive weight gets at least one unit (so it can be chosen, and the estimator stays
/// unbiased); the largest items absorb the others' rounding so that the units add up to
/// 2^bits. Items of weight 0 are never chosen.
class DiscreteDistribution {
 public:
  DiscreteDistribution() = default;
  /// Throws std::invalid_argument when no weight is positive, a weight is negative or not
  /// finite, or there are more than 2^(bits - 2) items.
  DiscreteDistribution(std::span<const double> weights, int bits);

  size_t size() const { return cdf_.size(); }
  int bits() const { return bits_; }
  /// Upper end (exclusive) of item k's range of m; cdf(size() - 1) = 2^bits.
  uint64_t cdf(size_t k) const { return cdf_[k]; }
  /// The item chosen by m in [0, 2^bits): the first k with m < cdf(k).
  size_t sample(uint64_t m) const;
  /// The item chosen by 64 uniform random bits (their top `bits` bits are m).
  size_t sample_bits(uint64_t random_bits) const { return sample(random_bits >> (64 - bits_)); }
  /// Probability of choosing item k: its range's length / 2^bits (exact in double).
  double probability(size_t k) const;

 private:
  std::vector<uint64_t> cdf_;
  int bits_ = 0;
};

}  // namespace rayscout
