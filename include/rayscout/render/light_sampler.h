// Area light sampling: emissive triangles chosen by power, points uniform on the triangle.
#pragma once

#include <cstdint>
#include <vector>

#include "rayscout/core/discrete_distribution.h"
#include "rayscout/scene/scene.h"

namespace rayscout {

/// A point sampled on an area light.
struct LightSample {
  Vec3 p;             ///< point on the emitter
  Vec3 n;             ///< unit geometric normal of the emitter (the side that emits)
  Vec3 emission;      ///< Le
  float pdf_area = 0; ///< probability density per unit area (choice of triangle included)
  double choice_probability = 0;  ///< probability with which this triangle was chosen
};

/// Emissive triangles of a scene with a discrete distribution proportional to
/// area * mean(emission). Emission is one-sided, on the side of the geometric normal
/// (v1 - v0) x (v2 - v0) (counter-clockwise winding faces the lit side, as in OBJ).
/// The choice uses 53 random bits and a DiscreteDistribution on the 2^-53 grid, so the
/// probability reported is exactly the probability of the choice, also for a light 1e-7 as
/// bright as its neighbour (which a 24-bit u would over- or under-sample, or never choose).
class LightSampler {
 public:
  /// Keeps a pointer to scene (it must outlive the sampler).
  explicit LightSampler(const Scene& scene);
  /// No emissive triangle with positive power.
  bool empty() const { return prims_.empty(); }
  /// Chooses a triangle with the top 53 of 64 uniform random bits (PathSampler::bits) and a
  /// uniform point on it with (u1, u2).
  LightSample sample(uint64_t choice_bits, float u1, float u2) const;
  /// The choice among the emissive triangles (in the order of their primitive ids).
  const DiscreteDistribution& distribution() const { return choice_; }
  /// Density per unit area with which sample() returns a point of triangle prim (the
  /// LightSample::pdf_area of its points); 0 for a triangle it never chooses.
  float pdf_area(uint32_t prim) const;

 private:
  const Scene* scene_;
  std::vector<uint32_t> prims_;
  DiscreteDistribution choice_;
};

}  // namespace rayscout
