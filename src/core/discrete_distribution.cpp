// DiscreteDistribution: weights rounded to integer ranges of a 2^bits grid.
#include "rayscout/core/discrete_distribution.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rayscout {

DiscreteDistribution::DiscreteDistribution(std::span<const double> weights, int bits) : bits_(bits) {
  if (bits < 2 || bits > 53) throw std::invalid_argument("DiscreteDistribution: bits must be in [2, 53]");
  const uint64_t units = uint64_t(1) << bits;
  if (weights.size() > (units >> 2)) throw std::invalid_argument("DiscreteDistribution: too many items");
  double total = 0;
  for (double w : weights) {
    if (!(w >= 0) || !std::isfinite(w)) throw std::invalid_argument("DiscreteDistribution: weight < 0 or not finite");
    total += w;
  }
  if (!(total > 0) || !std::isfinite(total)) throw std::invalid_argument("DiscreteDistribution: no positive weight");
  // Round each share to whole units, at least one for a positive weight; the largest item
  // absorbs the rounding so the units add up to 2^bits (it has >= 2^bits / n >= 4 units, and
  // the rounding moves at most n / 2 + n, so it keeps at least one).
  std::vector<uint64_t> count(weights.size(), 0);
  uint64_t sum = 0;
  size_t largest = 0;
  for (size_t k = 0; k < weights.size(); ++k) {
    if (weights[k] > 0) count[k] = std::max<uint64_t>(1, uint64_t(std::llround(weights[k] / total * double(units))));
    sum += count[k];
    if (weights[k] > weights[largest]) largest = k;
  }
  if (sum > units) count[largest] -= std::min(count[largest] - 1, sum - units);
  else count[largest] += units - sum;
  cdf_.resize(count.size());
  uint64_t running = 0;
  for (size_t k = 0; k < count.size(); ++k) cdf_[k] = running += count[k];
  if (running != units) throw std::invalid_argument("DiscreteDistribution: weights too uneven to quantise");
}

size_t DiscreteDistribution::sample(uint64_t m) const {
  // The last item has a positive count, so m < 2^bits always finds one; clamp for m beyond.
  const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), m);
  return std::min(size_t(it - cdf_.begin()), cdf_.size() - 1);
}

double DiscreteDistribution::probability(size_t k) const {
  const uint64_t lo = k ? cdf_[k - 1] : 0;
  return std::ldexp(double(cdf_[k] - lo), -bits_);
}

}  // namespace rayscout
