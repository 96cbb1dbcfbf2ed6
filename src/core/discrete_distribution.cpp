// DiscreteDistribution: weights rounded to integer ranges of a 2^bits grid.
#include "rayscout/core/discrete_distribution.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace rayscout {

DiscreteDistribution::DiscreteDistribution(std::span<const double> weights, int bits) : bits_(bits) {
  if (bits < 2 || bits > 53) throw std::invalid_argument("DiscreteDistribution: bits must be in [2, 53]");
  const uint64_t units = uint64_t(1) << bits;
  if (weights.size() > (units >> 2)) throw std::invalid_argument("DiscreteDistribution: too many items");
  double total = 0, heaviest = 0;
  for (double w : weights) {
    if (!(w >= 0) || !std::isfinite(w)) throw std::invalid_argument("DiscreteDistribution: weight < 0 or not finite");
    total += w;
    heaviest = std::max(heaviest, w);
  }
  if (!(heaviest > 0)) throw std::invalid_argument("DiscreteDistribution: no positive weight");
  // Finite weights whose sum overflows (two of 1e308) are shares of a sum scaled by a power of
  // two, which leaves every share as it was.
  const int shift = std::isfinite(total) ? 0 : std::ilogb(heaviest) + 1;
  if (shift) {
    total = 0;
    for (double w : weights) total += std::ldexp(w, -shift);
  }
  // Round each share to whole units, at least one for a positive weight; the largest item
  // absorbs the rounding so the units add up to 2^bits. When the one-unit floors of many small
  // items outweigh it (256 items, half of them tiny, on 2^10 units), the next largest give up
  // units too, each keeping one: the units beyond one per item, sum - n, cover the excess
  // sum - 2^bits, since n <= 2^bits / 4.
  std::vector<uint64_t> count(weights.size(), 0);
  uint64_t sum = 0;
  size_t largest = 0;
  for (size_t k = 0; k < weights.size(); ++k) {
    if (weights[k] > 0)
      count[k] = std::max<uint64_t>(1, uint64_t(std::llround(std::ldexp(weights[k], -shift) / total * double(units))));
    sum += count[k];
    if (weights[k] > weights[largest]) largest = k;
  }
  if (sum > units) {
    uint64_t excess = sum - units;
    auto give_up = [&](size_t k) {
      const uint64_t take = std::min(count[k] > 0 ? count[k] - 1 : 0, excess);
      count[k] -= take;
      excess -= take;
    };
    give_up(largest);
    if (excess) {
      std::vector<size_t> order(count.size());
      std::iota(order.begin(), order.end(), size_t(0));
      std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return count[a] > count[b]; });
      for (size_t k : order)
        if (excess) give_up(k);
    }
  } else {
    count[largest] += units - sum;
  }
  cdf_.resize(count.size());
  uint64_t running = 0;
  for (size_t k = 0; k < count.size(); ++k) cdf_[k] = running += count[k];
  if (running != units) throw std::invalid_argument("DiscreteDistribution: weights too uneven to quantise");
}

size_t DiscreteDistribution::sample(uint64_t m) const {
  // cdf(size() - 1) = 2^bits, so m < 2^bits finds the item whose (non-empty) range holds it;
  // m beyond is clamped to 2^bits - 1, never to a last item of weight 0 (an empty range).
  const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), std::min(m, cdf_.back() - 1));
  return size_t(it - cdf_.begin());
}

double DiscreteDistribution::probability(size_t k) const {
  const uint64_t lo = k ? cdf_[k - 1] : 0;
  return std::ldexp(double(cdf_[k] - lo), -bits_);
}

}  // namespace rayscout
