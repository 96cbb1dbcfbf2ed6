// Area light sampling: emissive triangles chosen by power, points uniform on the triangle.
#pragma once

#include <cstdint>
#include <vector>

#include "rayscout/scene/scene.h"

namespace rayscout {

/// A point sampled on an area light.
struct LightSample {
  Vec3 p;             ///< point on the emitter
  Vec3 n;             ///< unit geometric normal of the emitter (the side that emits)
  Vec3 emission;      ///< Le
  float pdf_area = 0; ///< probability density per unit area (choice of triangle included)
};

/// Emissive triangles of a scene with a discrete distribution proportional to
/// area * mean(emission). Emission is one-sided, on the side of the geometric normal
/// (v1 - v0) x (v2 - v0) (counter-clockwise winding faces the lit side, as in OBJ).
class LightSampler {
 public:
  /// Keeps a pointer to scene (it must outlive the sampler).
  explicit LightSampler(const Scene& scene);
  /// No emissive triangle with positive power.
  bool empty() const { return prims_.empty(); }
  /// Chooses a triangle with u0 and a uniform point on it with (u1, u2).
  LightSample sample(float u0, float u1, float u2) const;

 private:
  const Scene* scene_;
  std::vector<uint32_t> prims_;
  std::vector<float> cdf_;   // inclusive, normalised, last = 1
  std::vector<float> pmf_;
};

}  // namespace rayscout
