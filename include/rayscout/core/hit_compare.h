// Ray-by-ray comparison of hit batches, shared by tests and `rayscout compare-hits`.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "rayscout/core/ray.h"
#include "rayscout/core/triangle.h"

namespace rayscout {

/// How compare_hits judges two hit batches.
struct HitCompareConfig {
  /// t agrees when |t - t_ref| <= rel_tol * scale, scale = max(1, |t_ref|) without `rays`.
  /// 0 = bit-identical: the same triangle (an exact tie must be broken the same way, by the
  /// smaller id), the same t and the same u, v, bit for bit.
  float rel_tol = 1e-5f;
  /// The rays both batches traced (optional, must outlive the call). With them the tolerance
  /// is in world space, the precision float coordinates really have: t agrees when
  /// |t - t_ref| |d| <= rel_tol * max(1, |o|, |o + t_ref d|) (max norms). A hit near the
  /// origin far from the world origin then gets the few ulps of its coordinates, which a
  /// tolerance relative to t alone denies (e.g. 0.02 in t = 2e-5 world units on a
  /// 1e-3-long direction at 50 units from the origin).
  const RayBatch* rays = nullptr;
  /// Disagreements at a grazing contact (see is_grazing) are counted in HitDiff::grazing
  /// instead of as errors: a ray exactly through a mesh's boundary edge or vertex, or a ray
  /// starting on a surface, may or may not hit depending on the last bit of arithmetic.
  /// Off (default) for our own accelerators, which share one kernel; on for Embree.
  /// Ignored when rel_tol is 0: bit-identical excuses nothing.
  bool allow_grazing = false;
  /// Without triangles: a hit is grazing when a barycentric coordinate (u, v or 1-u-v) is
  /// <= edge_eps.
  float edge_eps = 1e-4f;
  /// The triangles both batches were traced against, indexed by Hit::prim (optional, used
  /// with `rays`; must outlive the call). With them a contact is grazing when float
  /// arithmetic cannot decide it (see is_grazing), whatever the triangle's size, and edge_eps
  /// is not used.
  std::span<const Triangle> triangles;
  /// With triangles: the precision of the two tracers' arithmetic, in float ulps (2^-24) of
  /// the largest coordinate of the ray's origin and the triangle's vertices. Every
  /// disagreement of Embree's robust mode with ours measured so far needs 1 (Sibenik, Sponza,
  /// Conference; rays aimed at vertices, edges, in the plane, from the surface).
  float ulps = 4.0f;

  /// Whether a disagreement at a grazing contact is counted apart instead of as an error.
  bool excuses_grazing() const { return allow_grazing && rel_tol > 0.0f; }
};

/// Whether float arithmetic may decide the contact h either way; `ray`: the index of the hit's
/// ray in config.rays, when given.
/// Without triangles: a hit on an edge or vertex of its triangle (a barycentric <= edge_eps)
/// or at t within the tolerance of 0 (a ray leaving the surface it starts on).
/// With triangles and rays, in double precision, tol = ulps 2^-24 max(|o|, |v0|, |v1|, |v2|)
/// (largest coordinates): the ray's line meets the triangle with its edges grown by tol, and
/// passes an edge by less than tol, measured as (e x d) . (o - a) / (|e| |d|) for the edge e
/// from vertex a, which is the in-plane distance from the edge times the cosine of the
/// incidence angle (so a ray nearly in the plane is grazing everywhere, a tiny triangle is
/// judged in world units, not barycentrics), or an end of the segment (at tmin, at tmax when
/// finite) lies within tol of the plane.
bool is_grazing(const Hit& h, const HitCompareConfig& config, size_t ray = 0);

/// Disagreements between a reference and a candidate hit batch.
struct HitDiff {
  size_t rays = 0;          ///< rays compared
  size_t both_hit = 0;      ///< rays both batches hit
  size_t hit_miss = 0;      ///< one hits, the other misses
  size_t other_prim = 0;    ///< both hit, different triangle, t not within tolerance (any t when rel_tol = 0)
  size_t t_mismatch = 0;    ///< same triangle, |t - t_ref| > rel_tol * scale
  size_t uv_mismatch = 0;   ///< rel_tol = 0 only: same triangle and t, different u or v bits
  /// Different triangle at the same t (within tolerance, rel_tol > 0): not an error. With
  /// triangles only a true tie counts: the ray meets both, and where its line crosses each
  /// plane (computed, not reported) lies within is_grazing's tol of the other's plane (a shared
  /// edge, coplanar triangles); otherwise it is judged as any other different triangle.
  size_t ties = 0;
  /// Disagreements at a grazing contact, and with triangles also at distances float cannot
  /// order (each hit point within is_grazing's tol of the other's plane; allow_grazing
  /// only): not an error.
  size_t grazing = 0;
  /// Max and 99th percentile of |t - t_ref| / scale (HitCompareConfig::rel_tol) over rays
  /// that both hit (the same triangle or a tie).
  double max_rel_diff = 0.0, p99_rel_diff = 0.0;
  std::string first;        ///< description of the first disagreement
  /// With triangles and rays: how far one side's hit points o + t d lie off their triangles'
  /// planes, in ulps (2^-24) of the largest coordinate of the ray's origin and the triangle's
  /// vertices (the unit of HitCompareConfig::ulps), over that side's hits. What a tracer's t
  /// is worth, independent of the other side; all 0 without triangles.
  struct PlaneOffsets {
    size_t hits = 0;
    double median = 0.0, p99 = 0.0, max = 0.0;
  };
  PlaneOffsets ref_offsets, got_offsets;
  bool ok() const { return hit_miss == 0 && other_prim == 0 && t_mismatch == 0 && uv_mismatch == 0; }
};

/// Compares ray by ray. With rel_tol > 0 a different triangle at the same t (within
/// tolerance; with triangles, also where float cannot order the two) is a tie and not counted
/// as an error; with rel_tol = 0 it is an error.
HitDiff compare_hits(const HitBatch& ref, const HitBatch& got, const HitCompareConfig& config);
/// Same, with config {rel_tol} (no grazing allowance).
HitDiff compare_hits(const HitBatch& ref, const HitBatch& got, float rel_tol = 1e-5f);

/// Disagreements between two occlusion results (one byte per ray, 1 = occluded).
struct OcclusionDiff {
  size_t rays = 0;
  size_t occluded_ref = 0, occluded_got = 0;  ///< occluded rays in each
  size_t differ = 0;    ///< rays where they disagree (grazing ones excluded)
  size_t grazing = 0;   ///< disagreements explained by a grazing closest hit
  std::string first;    ///< description of the first disagreement
  bool ok() const { return differ == 0; }
};

/// Compares occlusion ray by ray. With the closest hits of the same rays from both sides
/// (optional) and config.allow_grazing, a disagreement is grazing when the side that says
/// "occluded" has a grazing closest hit: its only blocker touches an edge or the origin.
OcclusionDiff compare_occlusion(const std::vector<uint8_t>& ref, const std::vector<uint8_t>& got,
                                const HitCompareConfig& config = {}, const HitBatch* ref_hits = nullptr,
                                const HitBatch* got_hits = nullptr);

}  // namespace rayscout
