// The median of repeated measurements, as every timing in rayscout reports it.
#pragma once

#include <algorithm>
#include <numeric>
#include <vector>

namespace rayscout {

/// Median of v (the mean of the two middle values for an even count); v must not be empty.
inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : std::midpoint(v[n / 2 - 1], v[n / 2]);  // (a + b) / 2 overflows above DBL_MAX / 2
}

}  // namespace rayscout
