// compare_hits / compare_occlusion: ray-by-ray agreement of two trace results.
#include "rayscout/core/hit_compare.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <string>

#include "rayscout/core/dvec3.h"

namespace rayscout {

namespace {

// The t difference that counts as rel_tol = 1 for ray i hitting at t_ref (HitCompareConfig).
float t_scale(const HitCompareConfig& config, size_t i, float t_ref) {
  const float relative = std::max(1.0f, std::fabs(t_ref));  // without rays, or for a degenerate one
  if (!config.rays || i >= config.rays->size()) return relative;
  const Ray r = (*config.rays)[i];
  const float len = length(r.dir);
  const Vec3 p = r.org + r.dir * t_ref;
  const float world = std::max({1.0f, max_component(abs(r.org)), max_component(abs(p))});
  if (!(len > 0.0f) || !std::isfinite(len) || !std::isfinite(world)) return relative;
  return world / len;
}

bool same_bits(float a, float b) { return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b); }

// The ray and the triangles of a contact in double (where float inputs are exact), with the
// precision float coordinates of that size have: config.ulps ulps of the largest one.
struct Contact {
  DVec3 o, d;
  double tol;
  Contact(const Ray& r, std::initializer_list<const Triangle*> tris, float ulps) : o(r.org), d(r.dir) {
    double m = max_abs(o);
    for (const Triangle* t : tris)
      for (const Vec3& v : {t->v0, t->v1, t->v2}) m = std::max(m, max_abs(DVec3(v)));
    tol = double(ulps) * 0x1p-24 * m;
  }
  static DVec3 normal(const Triangle& tri) { return cross(DVec3(tri.v1) - DVec3(tri.v0), DVec3(tri.v2) - DVec3(tri.v0)); }
  // Signed distance of o + t d from the triangle's plane; NaN for a degenerate triangle.
  double plane_distance(const Triangle& tri, double t) const {
    const DVec3 n = normal(tri);
    return dot(n, o + d * t - DVec3(tri.v0)) / length(n);
  }
  // Where the ray's line crosses the triangle's plane, exactly (but for rounding in double);
  // NaN or infinite for a ray parallel to it or a degenerate triangle.
  double plane_t(const Triangle& tri) const {
    const DVec3 n = normal(tri);
    return dot(n, DVec3(tri.v0) - o) / dot(n, d);
  }
  bool near_plane(const Triangle& tri, double t) const {
    return std::isfinite(t) && !(std::fabs(plane_distance(tri, t)) > tol);  // NaN: degenerate
  }
  // The ray's edge functions (e x d) . (o - a) / (|e| |d|), edge e from vertex a: where the
  // ray's line crosses the plane, the in-plane distance from each edge times the cosine of the
  // incidence angle, of one sign inside the triangle. Both watertight tests (ours, Embree's
  // robust Pluecker test) decide a hit by their signs. 0 for an edge of length 0.
  std::array<double, 3> edge_functions(const Triangle& tri) const {
    const DVec3 v[3] = {DVec3(tri.v0), DVec3(tri.v1), DVec3(tri.v2)};
    std::array<double, 3> f{};
    for (int i = 0; i < 3; ++i) {
      const DVec3 e = v[(i + 1) % 3] - v[i];
      const double scale = length(e) * length(d);
      f[i] = scale > 0.0 ? dot(cross(e, d), o - v[i]) / scale : 0.0;
    }
    return f;
  }
  // Whether the ray's line meets the triangle, edges grown by tol: a claimed contact must.
  bool passes(const std::array<double, 3>& f) const {
    return std::min({f[0], f[1], f[2]}) >= -tol || std::max({f[0], f[1], f[2]}) <= tol;
  }
  bool near_edge(const std::array<double, 3>& f) const {
    return std::min({std::fabs(f[0]), std::fabs(f[1]), std::fabs(f[2])}) <= tol;
  }
};

// The ray of index i and the triangle of hit h, when config has both.
bool has_geometry(const HitCompareConfig& config, size_t i, const Hit& h) {
  return config.rays && i < config.rays->size() && h.prim < config.triangles.size();
}

// Whether two hits of ray i lie at distances float cannot order: the ray meets both triangles
// (within tol) and each hit point lies within tol of the other's plane (for one triangle:
// |t_a - t_b| |n . d| <= tol). The points are o + t d at the reported t, or, for a true tie
// (at_crossings), where the line crosses each plane, whatever distances the tracers reported
// (a shared edge, coplanar triangles).
bool indistinct(const Hit& a, const Hit& b, const HitCompareConfig& config, size_t i, bool at_crossings = false) {
  if (!has_geometry(config, i, a) || !has_geometry(config, i, b)) return false;
  const Triangle &ta = config.triangles[a.prim], &tb = config.triangles[b.prim];
  const Contact c((*config.rays)[i], {&ta, &tb}, config.ulps);
  const double t_a = at_crossings ? c.plane_t(ta) : a.t, t_b = at_crossings ? c.plane_t(tb) : b.t;
  return c.passes(c.edge_functions(ta)) && c.passes(c.edge_functions(tb)) && c.near_plane(ta, t_b) &&
         c.near_plane(tb, t_a);
}

// The q-quantile of v (reordered), 0 for an empty v.
double quantile(std::vector<double>& v, double q) {
  if (v.empty()) return 0.0;
  const size_t k = std::min(v.size() - 1, size_t(std::ceil(q * double(v.size()))) - (q > 0.0));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

// HitDiff::PlaneOffsets of a batch's hits (config has rays and triangles).
HitDiff::PlaneOffsets plane_offsets(const HitBatch& hits, const HitCompareConfig& config) {
  std::vector<double> ulps;
  for (size_t i = 0; i < hits.size(); ++i) {
    const Hit h = hits[i];
    if (!h.hit() || !has_geometry(config, i, h)) continue;
    const Triangle& tri = config.triangles[h.prim];
    const Contact c((*config.rays)[i], {&tri}, 1.0f);  // tol = 1 ulp
    const double off = std::fabs(c.plane_distance(tri, h.t)) / c.tol;
    if (std::isfinite(off)) ulps.push_back(off);
  }
  HitDiff::PlaneOffsets p;
  p.hits = ulps.size();
  if (ulps.empty()) return p;
  p.max = *std::max_element(ulps.begin(), ulps.end());
  p.p99 = quantile(ulps, 0.99);
  p.median = quantile(ulps, 0.5);
  return p;
}

}  // namespace

bool is_grazing(const Hit& h, const HitCompareConfig& config, size_t ray) {
  if (!h.hit()) return false;
  if (!config.triangles.empty() && config.rays) {
    if (!has_geometry(config, ray, h)) return false;
    const Ray r = (*config.rays)[ray];
    const Triangle& tri = config.triangles[h.prim];
    const Contact c(r, {&tri}, config.ulps);
    if (!std::isfinite(max_abs(c.o)) || !std::isfinite(max_abs(c.d)) || !(length(c.d) > 0.0)) return false;
    const std::array<double, 3> f = c.edge_functions(tri);
    return c.passes(f) && (c.near_edge(f) || c.near_plane(tri, r.tmin) || c.near_plane(tri, r.tmax));
  }
  const float w = 1.0f - h.u - h.v;
  return std::min({h.u, h.v, w}) <= config.edge_eps ||
         std::fabs(h.t) <= config.rel_tol * t_scale(config, ray, 0.0f);
}

HitDiff compare_hits(const HitBatch& ref, const HitBatch& got, float rel_tol) {
  HitCompareConfig config;
  config.rel_tol = rel_tol;
  return compare_hits(ref, got, config);
}

HitDiff compare_hits(const HitBatch& ref, const HitBatch& got, const HitCompareConfig& config) {
  HitDiff d;
  auto note = [&](size_t i, const char* what) {
    if (!d.first.empty()) return;
    d.first = "ray " + std::to_string(i) + ": " + what + " (ref t=" + std::to_string(ref.t[i]) +
              " prim=" + std::to_string(ref.prim[i]) + ", got t=" + std::to_string(got.t[i]) +
              " prim=" + std::to_string(got.prim[i]) + ")";
  };
  const size_t n = std::min(ref.size(), got.size());
  d.rays = n;
  if (ref.size() != got.size()) {
    d.hit_miss = std::max(ref.size(), got.size()) - n;
    d.first = "batch sizes differ: " + std::to_string(ref.size()) + " vs " + std::to_string(got.size());
  }
  const bool exact = config.rel_tol == 0.0f;  // bit-identical: no ties, u and v compared too
  const bool judged = !config.triangles.empty() && config.rays;  // contacts judged from the triangles
  std::vector<double> rel;
  for (size_t i = 0; i < n; ++i) {
    const Hit r = ref[i], g = got[i];
    if (r.hit() != g.hit()) {
      // The side that hit found a contact the other missed.
      if (config.excuses_grazing() && is_grazing(r.hit() ? r : g, config, i)) { ++d.grazing; continue; }
      ++d.hit_miss;
      note(i, "hit/miss");
      continue;
    }
    if (!r.hit()) continue;
    ++d.both_hit;
    // Equal distances differ by 0, infinite ones too (a hit at t = +-inf: inf - inf is NaN).
    const float diff = g.t == r.t ? 0.0f : std::fabs(g.t - r.t) / t_scale(config, i, r.t);
    // Bit-identical tells t = -0 from +0 (== does not), as it does u and v.
    const bool t_close = exact ? same_bits(g.t, r.t) : diff <= config.rel_tol;
    if (r.prim != g.prim) {
      // With triangles, a tie must be one: the reported distances may be a few ulps off
      // (they agree within rel_tol), the triangles' own may not.
      if (t_close && !exact && (!judged || indistinct(r, g, config, i, /*at_crossings=*/true))) {
        ++d.ties;
      } else if (config.excuses_grazing() &&
                 (is_grazing(g.t < r.t ? g : r, config, i) || indistinct(r, g, config, i))) {
        ++d.grazing;  // the nearer contact is grazing (the other side passed it by), or neither is nearer
        continue;
      } else {
        ++d.other_prim;
        note(i, "different triangle");
        continue;
      }
    } else if (!t_close) {
      if (config.excuses_grazing() && indistinct(r, g, config, i)) {
        ++d.grazing;  // nearly in the plane: float cannot tell the distance better
        continue;
      }
      ++d.t_mismatch;
      note(i, "distance");
    } else if (exact && !(same_bits(g.u, r.u) && same_bits(g.v, r.v))) {
      ++d.uv_mismatch;
      note(i, "barycentrics");
    }
    rel.push_back(diff);
  }
  if (!rel.empty()) {
    d.max_rel_diff = *std::max_element(rel.begin(), rel.end());
    d.p99_rel_diff = quantile(rel, 0.99);
  }
  if (judged) {
    d.ref_offsets = plane_offsets(ref, config);
    d.got_offsets = plane_offsets(got, config);
  }
  return d;
}

OcclusionDiff compare_occlusion(const std::vector<uint8_t>& ref, const std::vector<uint8_t>& got,
                                const HitCompareConfig& config, const HitBatch* ref_hits,
                                const HitBatch* got_hits) {
  OcclusionDiff d;
  const size_t n = std::min(ref.size(), got.size());
  d.rays = n;
  if (ref.size() != got.size()) {
    d.differ = std::max(ref.size(), got.size()) - n;
    d.first = "sizes differ: " + std::to_string(ref.size()) + " vs " + std::to_string(got.size());
  }
  for (size_t i = 0; i < n; ++i) {
    d.occluded_ref += ref[i] != 0;
    d.occluded_got += got[i] != 0;
    if ((ref[i] != 0) == (got[i] != 0)) continue;
    const HitBatch* blocker = ref[i] ? ref_hits : got_hits;
    if (config.excuses_grazing() && blocker && i < blocker->size() && is_grazing((*blocker)[i], config, i)) {
      ++d.grazing;
      continue;
    }
    if (d.differ++ == 0 && d.first.empty())
      d.first = "ray " + std::to_string(i) + ": ref " + (ref[i] ? "occluded" : "clear") + ", got " +
                (got[i] ? "occluded" : "clear");
  }
  return d;
}

}  // namespace rayscout
