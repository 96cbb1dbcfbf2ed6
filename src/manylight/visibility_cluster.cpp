// VisibilityCluster: clustering, cluster-pair visibility and the VPL-cluster distributions.
// After Wu & Chuang 2013 (ref. [5] of Nabata & Iwasaki 2019; the paper's sec. 3 and fig. 1(a)-(c)
// use it); where ours differs, docs/manylight.md (VisibilityCluster, Parameters) says so.
#include "rayscout/manylight/visibility_cluster.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <string>

#include <tbb/parallel_for.h>

#include "rayscout/core/discrete_distribution.h"
#include "rayscout/core/input_error.h"
#include "rayscout/core/stopwatch.h"
#include "rayscout/manylight/channel_mean.h"
#include "rayscout/render/bsdf.h"
#include "ray_offset.h"
#include "rng.h"

namespace rayscout {

namespace {

using Feature = std::array<float, 6>;

// rayscout's clustering (docs/manylight.md, VisibilityCluster): recursive median bisection of
// 6-D features, a simplification of Wu & Chuang's clustering.
int ceil_log2(size_t n) { return n <= 1 ? 0 : int(std::bit_width(n - 1)); }

void bisect(std::vector<Feature>& f, std::vector<uint32_t>& order, size_t lo, size_t hi, int depth,
            std::vector<uint32_t>& begins) {
  // Fewer than two items: one cluster, so no cluster is ever empty (there may be fewer than 2^depth).
  if (depth == 0 || hi - lo < 2) {
    begins.push_back(uint32_t(lo));
    return;
  }
  Feature lo_f, hi_f;
  lo_f.fill(INFINITY);
  hi_f.fill(-INFINITY);
  for (size_t i = lo; i < hi; ++i)
    for (int d = 0; d < 6; ++d) {
      lo_f[d] = std::min(lo_f[d], f[order[i]][d]);
      hi_f[d] = std::max(hi_f[d], f[order[i]][d]);
    }
  int axis = 0;
  for (int d = 1; d < 6; ++d)
    if (hi_f[d] - lo_f[d] > hi_f[axis] - lo_f[axis]) axis = d;
  const size_t mid = lo + (hi - lo) / 2;
  std::nth_element(order.begin() + lo, order.begin() + mid, order.begin() + hi,
                   [&](uint32_t a, uint32_t b) { return f[a][axis] < f[b][axis] || (f[a][axis] == f[b][axis] && a < b); });
  bisect(f, order, lo, mid, depth - 1, begins);
  bisect(f, order, mid, hi, depth - 1, begins);
}

}  // namespace

size_t cluster_count(size_t items, int wanted) {
  if (items == 0) return 0;
  return std::min(items, size_t(1) << ceil_log2(std::min(items, size_t(std::max(1, wanted)))));
}

Clustering cluster_points(std::span<const Vec3> positions, std::span<const Vec3> normals,
                          float diagonal, float normal_weight, int clusters) {
  Clustering c;
  const size_t n = positions.size();
  std::vector<Feature> f(n);
  const float inv = diagonal > 0 ? 1.0f / diagonal : 1.0f;
  for (size_t i = 0; i < n; ++i)
    f[i] = {positions[i].x * inv, positions[i].y * inv, positions[i].z * inv,
            normals[i].x * normal_weight, normals[i].y * normal_weight, normals[i].z * normal_weight};
  c.order.resize(n);
  for (size_t i = 0; i < n; ++i) c.order[i] = uint32_t(i);
  // More clusters than points cannot be made: bisection stops at single points anyway.
  if (n > 0) bisect(f, c.order, 0, n, ceil_log2(cluster_count(n, clusters)), c.begin);
  c.begin.push_back(uint32_t(n));
  return c;
}

// t_i = I f_r G of the paper's sec. 2.2 (eq. 1 without V), with rayscout's optional G clamp.
Vec3 tentative_contribution(const Scene& scene, const ShadingPoint& sp, const Vpl& vpl, float clamp_distance) {
  const Vec3 d = vpl.position - sp.position;
  const float dist2 = dot(d, d);
  if (!(dist2 > 0.0f)) return Vec3(0.0f);
  const Vec3 w = d * (1.0f / std::sqrt(dist2));
  const float cos_x = dot(sp.normal, w);
  if (cos_x <= 0.0f) return Vec3(0.0f);
  const Vec3 intensity = vpl_intensity(vpl, scene, -w);
  if (max_component(intensity) <= 0.0f) return Vec3(0.0f);
  const Vec3 f = eval_bsdf(scene.materials[sp.material], sp.normal, sp.wo, w);
  return intensity * f * (cos_x / std::max(dist2, clamp_distance * clamp_distance));
}

Ray shadow_ray(const ShadingPoint& sp, const Vpl& vpl, float offset) {
  const Vec3 o = sp.position + sp.normal * offset;
  Vec3 y = vpl.position;
  if (vpl.kind != Vpl::Kind::Point) {
    // Offset the VPL end towards the shading point's side of its surface.
    const float side = dot(vpl.normal, sp.position - vpl.position) >= 0.0f ? 1.0f : -1.0f;
    y = y + vpl.normal * (side * offset);
  }
  return {o, 0.0f, y - o, 0.999f};
}

namespace {

/// What the member pairs sampled so far say about each cluster pair (index s * nl + l).
struct PairEstimates {
  std::vector<double> sum_t;                      ///< channel means of t_i summed ...
  std::vector<uint32_t> n_t;                      ///< ... over this many member pairs
  std::vector<uint32_t> n_traced, n_vis;          ///< shadow rays traced, and unoccluded
  explicit PairEstimates(size_t pairs) : sum_t(pairs, 0.0), n_t(pairs, 0), n_traced(pairs, 0), n_vis(pairs, 0) {}
};

/// Everything the sampling of cluster pairs reads.
struct PairSampling {
  const Scene& scene;
  std::span<const ShadingPoint> points;
  const VplSet& vpls;
  const ManylightConfig& config;
  const VisibilityClusters& vc;
  size_t nl;  ///< VPL clusters

  /// A random member pair of cluster pair pid: the shading point first, then the VPL.
  std::pair<const ShadingPoint*, const Vpl*> random_members(uint32_t pid, manylight_detail::Rng& rng) const {
    const size_t s = pid / nl, l = pid % nl;
    const uint32_t point = vc.shading.order[vc.shading.begin[s] + rng.below(uint32_t(vc.shading.count(s)))];
    const uint32_t vpl = vc.lights.order[vc.lights.begin[l] + rng.below(uint32_t(vc.lights.count(l)))];
    return {&points[point], &vpls.vpls[vpl]};
  }
  float contribution(const ShadingPoint& sp, const Vpl& vpl) const {
    return channel_mean(tentative_contribution(scene, sp, vpl, config.clamp_distance));
  }
};

/// Fig. 1(a): clusters the valid shading points and the VPLs.
void cluster_points_and_vpls(std::span<const ShadingPoint> points, const VplSet& vpls, float diag,
                             const ManylightConfig& config, VisibilityClusters& vc) {
  std::vector<uint32_t> valid;
  std::vector<Vec3> pos, nrm;
  for (uint32_t i = 0; i < points.size(); ++i) {
    if (!points[i].valid()) continue;
    valid.push_back(i);
    pos.push_back(points[i].position);
    nrm.push_back(points[i].normal);
  }
  vc.shading = cluster_points(pos, nrm, diag, config.normal_weight, config.shading_clusters);
  for (auto& id : vc.shading.order) id = valid[id];
  vc.shading_cluster_of.assign(points.size(), VisibilityClusters::kNoCluster);
  for (uint32_t c = 0; c < vc.shading.size(); ++c)
    for (uint32_t k = vc.shading.begin[c]; k < vc.shading.begin[c + 1]; ++k) vc.shading_cluster_of[vc.shading.order[k]] = c;

  pos.clear();
  nrm.clear();
  for (const Vpl& v : vpls.vpls) {
    pos.push_back(v.position);
    nrm.push_back(v.kind == Vpl::Kind::Point ? Vec3(0.0f) : v.normal);
  }
  vc.lights = cluster_points(pos, nrm, diag, config.normal_weight, config.vpl_clusters);
}

/// Fig. 1(b), sec. 3 (Wu & Chuang 2013): traces the shadow rays of `count` random member pairs
/// of every cluster pair in pair_ids; stream `pass` keeps the refinement's samples independent
/// of the first ones. Returns the number of shadow rays traced.
size_t sample_visibility(const PairSampling& ps, const Accelerator& accel, float offset,
                         std::span<const uint32_t> pair_ids, int count, uint64_t pass, PairEstimates& est) {
  size_t traced = 0;
  const size_t chunk_pairs = std::max<size_t>(1, (size_t(1) << 20) / size_t(std::max(1, count)));
  for (size_t c0 = 0; c0 < pair_ids.size(); c0 += chunk_pairs) {
    const size_t c1 = std::min(pair_ids.size(), c0 + chunk_pairs);
    const size_t m = (c1 - c0) * size_t(count);
    std::vector<float> contribution(m, 0.0f);
    std::vector<Ray> ray_of(m);
    tbb::parallel_for(tbb::blocked_range<size_t>(c0, c1), [&](const auto& range) {
      for (size_t k = range.begin(); k != range.end(); ++k) {
        manylight_detail::Rng rng(ps.config.seed, 0xC1A55 + pass, pair_ids[k]);
        for (int j = 0; j < count; ++j) {
          const auto [sp, vpl] = ps.random_members(pair_ids[k], rng);
          const size_t slot = (k - c0) * count + j;
          contribution[slot] = ps.contribution(*sp, *vpl);
          ray_of[slot] = shadow_ray(*sp, *vpl, offset);
        }
      }
    });
    // Only pairs that would contribute need a ray.
    RayBatch rays;
    std::vector<uint32_t> slot_of;
    for (size_t slot = 0; slot < m; ++slot)
      if (contribution[slot] > 0.0f) { rays.push_back(ray_of[slot]); slot_of.push_back(uint32_t(slot)); }
    std::vector<uint8_t> occ;
    accel.occluded(rays, occ);
    traced += rays.size();
    for (size_t k = c0; k < c1; ++k) {
      const uint32_t pid = pair_ids[k];
      for (int j = 0; j < count; ++j) {
        est.sum_t[pid] += contribution[(k - c0) * count + j];
        est.n_t[pid]++;
      }
    }
    for (size_t i = 0; i < rays.size(); ++i) {
      const uint32_t pid = pair_ids[c0 + slot_of[i] / count];
      est.n_traced[pid]++;
      est.n_vis[pid] += occ[i] ? 0u : 1u;
    }
  }
  return traced;
}

/// rayscout addition (docs/manylight.md, VisibilityCluster: contribution_samples).
/// Contributions need no rays: estimate them from many more member pairs than visibility,
/// so that a VPL cluster is rarely left at the uniform floor while some members matter.
void sample_contributions(const PairSampling& ps, size_t pairs, PairEstimates& est) {
  const int count = ps.config.contribution_samples;
  tbb::parallel_for(size_t(0), pairs, [&](size_t pid) {
    manylight_detail::Rng rng(ps.config.seed, 0xC0DE, pid);
    double sum = 0;
    for (int j = 0; j < count; ++j) {
      const auto [sp, vpl] = ps.random_members(uint32_t(pid), rng);
      sum += ps.contribution(*sp, *vpl);
    }
    est.sum_t[pid] += sum;
    est.n_t[pid] += uint32_t(count);
  });
}

/// rayscout's simplified stand-in for Wu & Chuang's refinement (docs/manylight.md, Refinement):
/// the pairs whose visibility is mixed and that carry an above-average share of their row;
/// only there does a better r change the pdf or the skip probability much.
std::vector<uint32_t> pairs_to_refine(const VisibilityClusters& vc, const std::vector<float>& weight, size_t ns,
                                      size_t nl) {
  std::vector<uint32_t> refine;
  for (size_t s = 0; s < ns; ++s) {
    double row = 0;
    for (size_t l = 0; l < nl; ++l) row += weight[s * nl + l];
    const double mean = row / double(nl);
    for (size_t l = 0; l < nl; ++l) {
      const size_t pid = s * nl + l;
      if (vc.r[pid] > 0.0f && vc.r[pid] < 1.0f && weight[pid] >= mean && weight[pid] > 0) refine.push_back(uint32_t(pid));
    }
  }
  return refine;
}

/// Fig. 1(c): the distribution over VPL clusters, here per shading cluster (the paper: per
/// shading point) with rayscout's r_floor and uniform_mix floors (docs/manylight.md, pmf).
void build_cluster_choice(const std::vector<float>& weight, size_t vpl_count, const ManylightConfig& config,
                          VisibilityClusters& vc) {
  const size_t ns = vc.shading.size(), nl = vc.lights.size();
  vc.vpl_cluster_choice.resize(ns);
  const double mix = std::clamp(double(config.uniform_mix), 0.0, 1.0);
  tbb::parallel_for(size_t(0), ns, [&](size_t s) {
    double row = 0;
    for (size_t l = 0; l < nl; ++l) row += weight[s * nl + l];
    std::vector<double> p(nl);
    for (size_t l = 0; l < nl; ++l) {
      const double uniform = double(vc.lights.count(l)) / double(vpl_count);
      p[l] = row > 0 ? (1.0 - mix) * weight[s * nl + l] / row + mix * uniform : uniform;
    }
    // Integer ranges of 53 random bits: the reported probability is the chance of the choice,
    // and every cluster keeps at least one unit (p > 0 for every VPL: unbiased).
    vc.vpl_cluster_choice[s] = DiscreteDistribution(p, 53);
  });
}

}  // namespace

VisibilityClusters build_visibility_clusters(const Scene& scene, const Accelerator& accel,
                                             std::span<const ShadingPoint> points,
                                             const VplSet& vpls, const ManylightConfig& config) {
  VisibilityClusters vc;
  auto t0 = SteadyClock::now();
  const float diag = length(scene.bounds().diagonal());
  cluster_points_and_vpls(points, vpls, diag, config, vc);
  vc.cluster_ms = ms_since(t0);

  // The average visibility r of every cluster pair from a few member pairs' shadow rays.
  t0 = SteadyClock::now();
  const size_t ns = vc.shading.size(), nl = vc.lights.size(), pairs = ns * nl;
  // Pair ids are 32-bit (PairSampling, the refinement list): beyond that they would wrap and
  // some pairs would be sampled twice, others never. (2^32 pairs take ~170 GB anyway.)
  if (pairs > UINT32_MAX)
    throw InputError("manylight: " + std::to_string(ns) + " shading clusters x " + std::to_string(nl) +
                     " VPL clusters = " + std::to_string(pairs) + " cluster pairs, more than 2^32 - 1: use fewer "
                     "--shading-clusters or --vpl-clusters");
  const float offset = manylight_detail::ray_offset(diag);
  const PairSampling ps{scene, points, vpls, config, vc, nl};
  PairEstimates est(pairs);
  if (config.contribution_samples > 0) sample_contributions(ps, pairs, est);
  std::vector<uint32_t> all(pairs);
  for (size_t i = 0; i < pairs; ++i) all[i] = uint32_t(i);
  vc.shadow_rays += sample_visibility(ps, accel, offset, all, std::max(1, config.visibility_samples), 0, est);

  vc.r.assign(pairs, 0.5f);
  std::vector<float> weight(pairs, 0.0f);
  // A pair's sampling weight C max(r, r_floor): the cluster's unoccluded contribution times its
  // visibility (sec. 3), floored by rayscout's r_floor (docs/manylight.md, pmf).
  auto estimate_pair = [&](size_t pid) {
    // Unknown (no pair faced each other): r = 0.5, the most uncertain prediction.
    vc.r[pid] = est.n_traced[pid] ? float(est.n_vis[pid]) / float(est.n_traced[pid]) : 0.5f;
    const double c = est.n_t[pid] ? est.sum_t[pid] / est.n_t[pid] * double(vc.lights.count(pid % nl)) : 0.0;
    weight[pid] = float(c * std::max(vc.r[pid], config.r_floor));
  };
  for (size_t pid = 0; pid < pairs; ++pid) estimate_pair(pid);
  if (config.refine_samples > 0) {
    const std::vector<uint32_t> refine = pairs_to_refine(vc, weight, ns, nl);
    vc.refined_pairs = refine.size();
    vc.shadow_rays += sample_visibility(ps, accel, offset, refine, config.refine_samples, 1, est);
    for (uint32_t pid : refine) estimate_pair(pid);
  }
  vc.visibility_ms = ms_since(t0);

  t0 = SteadyClock::now();
  build_cluster_choice(weight, vpls.vpls.size(), config, vc);
  if (config.override_r >= 0.0f && config.override_r <= 1.0f) std::fill(vc.r.begin(), vc.r.end(), config.override_r);
  vc.pmf_ms = ms_since(t0);
  return vc;
}

}  // namespace rayscout
