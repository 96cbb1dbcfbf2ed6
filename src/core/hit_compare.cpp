// compare_hits: ray-by-ray agreement of two hit batches.
#include "rayscout/core/hit_compare.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace rayscout {

HitDiff compare_hits(const HitBatch& ref, const HitBatch& got, float rel_tol) {
  HitDiff d;
  auto note = [&](size_t i, const char* what) {
    if (!d.first.empty()) return;
    d.first = "ray " + std::to_string(i) + ": " + what + " (ref t=" + std::to_string(ref.t[i]) +
              " prim=" + std::to_string(ref.prim[i]) + ", got t=" + std::to_string(got.t[i]) +
              " prim=" + std::to_string(got.prim[i]) + ")";
  };
  const size_t n = std::min(ref.size(), got.size());
  if (ref.size() != got.size()) {
    d.hit_miss = std::max(ref.size(), got.size()) - n;
    d.first = "batch sizes differ: " + std::to_string(ref.size()) + " vs " + std::to_string(got.size());
  }
  for (size_t i = 0; i < n; ++i) {
    const bool rh = ref.prim[i] != kInvalidId, gh = got.prim[i] != kInvalidId;
    if (rh != gh) { ++d.hit_miss; note(i, "hit/miss"); continue; }
    if (!rh) continue;
    const bool t_close = std::fabs(got.t[i] - ref.t[i]) <= rel_tol * std::max(1.0f, std::fabs(ref.t[i]));
    if (ref.prim[i] != got.prim[i]) {
      if (!t_close) { ++d.other_prim; note(i, "different triangle"); }
    } else if (!t_close) {
      ++d.t_mismatch; note(i, "distance");
    }
  }
  return d;
}

}  // namespace rayscout
