// Ray-by-ray comparison of hit batches, shared by tests and `rayscout compare-hits`.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "rayscout/core/ray.h"

namespace rayscout {

/// Disagreements between a reference and a candidate hit batch.
struct HitDiff {
  size_t hit_miss = 0;      ///< one hits, the other misses
  size_t other_prim = 0;    ///< both hit, different triangle and different t
  size_t t_mismatch = 0;    ///< same triangle, |t - t_ref| > rel_tol * max(1, t_ref)
  std::string first;        ///< description of the first disagreement
  bool ok() const { return hit_miss == 0 && other_prim == 0 && t_mismatch == 0; }
};

/// Compares ray by ray. A different triangle at the same t (within tolerance) is a true tie
/// and not counted.
HitDiff compare_hits(const HitBatch& ref, const HitBatch& got, float rel_tol = 1e-5f);

}  // namespace rayscout
