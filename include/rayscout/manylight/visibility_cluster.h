// VisibilityCluster (Wu & Chuang 2013): clusters of shading points and VPLs, the average
// visibility of every cluster pair, and the per-shading-cluster VPL-cluster distribution.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "rayscout/core/accelerator.h"
#include "rayscout/core/discrete_distribution.h"
#include "rayscout/manylight/manylight_config.h"
#include "rayscout/manylight/shading_points.h"
#include "rayscout/manylight/vpl.h"

namespace rayscout {

/// A partition of items into contiguous ranges of `order`.
struct Clustering {
  std::vector<uint32_t> order;   ///< item ids, cluster by cluster
  std::vector<uint32_t> begin;   ///< cluster c = order[begin[c] .. begin[c + 1])
  size_t size() const { return begin.empty() ? 0 : begin.size() - 1; }
  size_t count(size_t c) const { return begin[c + 1] - begin[c]; }
};

/// How many clusters cluster_points makes of `items` when asked for `wanted`: 2^ceil(log2(wanted))
/// (600 makes 1024), at most `items`.
size_t cluster_count(size_t items, int wanted);

/// Recursive median bisection of 6-D features (position / scene diagonal, normal * normal_weight)
/// along the widest dimension, to cluster_count(positions.size(), clusters) clusters of (almost)
/// equal size.
Clustering cluster_points(std::span<const Vec3> positions, std::span<const Vec3> normals,
                          float diagonal, float normal_weight, int clusters);

/// Everything sampling needs: clusters, r per pair, and per shading cluster a distribution over
/// VPL clusters P(v) = (1 - uniform_mix) C r' / (the row's sum of C r') + uniform_mix |V| / N,
/// where C is the estimated unoccluded contribution of VPL cluster v, r' = max(r, r_floor),
/// |V| its size and N the VPL count (uniform alone when every C r' of the row is 0).
struct VisibilityClusters {
  Clustering shading;               ///< over shading points (invalid points excluded)
  Clustering lights;                ///< over VPLs
  std::vector<uint32_t> shading_cluster_of;  ///< per shading point; kNoCluster for invalid ones
  std::vector<float> r;             ///< [s * lights.size() + v]: estimated average visibility
  /// [s]: the choice of a VPL cluster for the points of shading cluster s, on a 2^-53 grid:
  /// sample_bits() picks v with probability exactly probability(v), the weight the renderer uses
  std::vector<DiscreteDistribution> vpl_cluster_choice;
  size_t shadow_rays = 0;           ///< rays traced to estimate r (incl. refinement)
  size_t refined_pairs = 0;
  double cluster_ms = 0.0, visibility_ms = 0.0, pmf_ms = 0.0;

  static constexpr uint32_t kNoCluster = 0xFFFFFFFFu;
  size_t vpl_cluster_count() const { return lights.size(); }
};

/// Tentative contribution t = I f_r G (eq. 1 without V), W/(sr m^2) per colour, of vpl at
/// shading point sp; G = cos(theta_x) / max(d^2, clamp_distance^2).
Vec3 tentative_contribution(const Scene& scene, const ShadingPoint& sp, const Vpl& vpl,
                            float clamp_distance);

/// The shadow ray from sp to vpl: it leaves sp `offset` along sp's normal and ends `offset` off
/// the VPL's surface on sp's side (a point light's end is not moved), at 0.999 of the way.
Ray shadow_ray(const ShadingPoint& sp, const Vpl& vpl, float offset);

/// Builds the clusters, estimates r from config.visibility_samples random member pairs per
/// cluster pair (plus config.refine_samples for uncertain, above-average pairs) traced through
/// accel.occluded, and builds the sampling distributions.
VisibilityClusters build_visibility_clusters(const Scene& scene, const Accelerator& accel,
                                             std::span<const ShadingPoint> points,
                                             const VplSet& vpls, const ManylightConfig& config);

}  // namespace rayscout
