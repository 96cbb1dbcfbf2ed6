// Triangles and the watertight ray-triangle test every accelerator shares.
#pragma once

#include <cmath>
#include <limits>
#include <utility>

#include "rayscout/core/bounds3.h"
#include "rayscout/core/dvec3.h"
#include "rayscout/core/ray.h"

namespace rayscout {

/// A triangle by its three vertices (world space).
struct Triangle {
  Vec3 v0, v1, v2;

  Bounds3 bounds() const { Bounds3 b; b.extend(v0); b.extend(v1); b.extend(v2); return b; }
  Vec3 centroid() const { return (v0 + v1 + v2) * (1.0f / 3.0f); }
  /// Unnormalised geometric normal (v1 - v0) x (v2 - v0); its length is twice the area.
  Vec3 normal() const { return cross(v1 - v0, v2 - v0); }
  float area() const { return 0.5f * length(normal()); }
};

/// Per-ray constants of the watertight test (Woop, Benthin, Wald, JCGT 2013, sec. 3):
/// the axis kz of the largest direction component, the shear (sx, sy, sz) and the
/// reciprocal direction used by the slab test.
struct RayPrecomp {
  int kx = 0, ky = 1, kz = 2;
  float sx = 0, sy = 0, sz = 1;
  Vec3 inv_dir;

  /// Fields at their defaults (kz = z, no shear, inv_dir 0), to be filled from elsewhere
  /// without the divisions of the constructor below.
  RayPrecomp() = default;
  explicit RayPrecomp(const Vec3& dir) {
    kz = max_axis(abs(dir));
    kx = kz == 2 ? 0 : kz + 1;
    ky = kx == 2 ? 0 : kx + 1;
    if (dir[kz] < 0.0f) std::swap(kx, ky);  // keep the winding, so det's sign is meaningful
    sx = dir[kx] / dir[kz];
    sy = dir[ky] / dir[kz];
    sz = 1.0f / dir[kz];
    inv_dir = Vec3(1.0f / dir.x, 1.0f / dir.y, 1.0f / dir.z);
  }
};

/// min and max as SSE's minps / maxps and AVX-512's vminps / vmaxps compute them: the second
/// operand when either is NaN or both are equal (+0 and -0), so SIMD kernels match bit for bit.
constexpr float simd_min(float a, float b) { return a < b ? a : b; }
constexpr float simd_max(float a, float b) { return a > b ? a : b; }

/// The hit distance from the triangle's plane, t = n.a / n.d (n = tri.normal(), a = v0 - org),
/// as Embree computes it, rather than Woop's interpolation (eu az + ev bz + ew cz) / det: that
/// one's rounding grows with the triangle's length along the ray (up to 100 ulps off the plane
/// on Sponza's long slivers, enough to pick a triangle behind the right one; this one stays
/// within 7, docs/runs/zen5/session50). In the ray's (kx, ky, kz) order, n.d / d[kz] is
/// n[kx] sx + n[ky] sy + n[kz]. The result is clamped to the vertices' sheared depths
/// [lo, hi], where the interpolation lies by construction: a ray grazing the plane divides
/// by a denominator that is mostly rounding. A NaN quotient stays NaN.
/// One spelling for every kernel, in the lanes of L (L::F and add, mul, div, min, max, with
/// min and max as simd_min / simd_max): float (FloatLanes) for the scalar test, SIMD registers
/// for the BVH's block test and DACRT's leaves, so that their t are bit-identical. n and
/// a = v0 - org in the ray's (kx, ky, kz) order, the shear (sx, sy, sz), and the vertices'
/// sheared depths az, bz, cz.
template <class L, class F = typename L::F>
inline F plane_distance(F na, F nb, F nc, F aa, F ab, F ac, F sx, F sy, F sz, F az, F bz, F cz) {
  const F num = L::add(L::add(L::mul(na, aa), L::mul(nb, ab)), L::mul(nc, ac));
  const F den = L::add(L::add(L::mul(na, sx), L::mul(nb, sy)), nc);
  const F lo = L::min(L::min(az, bz), cz), hi = L::max(L::max(az, bz), cz);
  return L::min(hi, L::max(lo, L::div(L::mul(num, sz), den)));
}
/// The lane operations of plane_distance on one float.
struct FloatLanes {
  using F = float;
  static F add(F a, F b) { return a + b; }
  static F mul(F a, F b) { return a * b; }
  static F div(F a, F b) { return a / b; }
  static F min(F a, F b) { return simd_min(a, b); }
  static F max(F a, F b) { return simd_max(a, b); }
};

/// Watertight ray-triangle test (Woop et al. 2013, fig. 4), no back-face culling, with the
/// hit distance of plane_distance. Returns true and fills t, u, v when the ray hits at
/// tmin <= t <= tmax. Edges and vertices shared by two triangles are hit by at least one of
/// them; an edge function that is exactly zero is recomputed in double, as the paper recommends.
inline bool intersect_triangle(const Vec3& org, const RayPrecomp& rp, const Triangle& tri,
                               float tmin, float tmax, float& t, float& u, float& v) {
  const Vec3 a = tri.v0 - org, b = tri.v1 - org, c = tri.v2 - org;
  const float ax = a[rp.kx] - rp.sx * a[rp.kz], ay = a[rp.ky] - rp.sy * a[rp.kz];
  const float bx = b[rp.kx] - rp.sx * b[rp.kz], by = b[rp.ky] - rp.sy * b[rp.kz];
  const float cx = c[rp.kx] - rp.sx * c[rp.kz], cy = c[rp.ky] - rp.sy * c[rp.kz];
  float eu = cx * by - cy * bx;
  float ev = ax * cy - ay * cx;
  float ew = bx * ay - by * ax;
  if (eu == 0.0f || ev == 0.0f || ew == 0.0f) {
    eu = static_cast<float>(double(cx) * double(by) - double(cy) * double(bx));
    ev = static_cast<float>(double(ax) * double(cy) - double(ay) * double(cx));
    ew = static_cast<float>(double(bx) * double(ay) - double(by) * double(ax));
  }
  if ((eu < 0.0f || ev < 0.0f || ew < 0.0f) && (eu > 0.0f || ev > 0.0f || ew > 0.0f)) return false;
  const float det = eu + ev + ew;
  if (det == 0.0f) return false;
  const float az = rp.sz * a[rp.kz], bz = rp.sz * b[rp.kz], cz = rp.sz * c[rp.kz];
  auto distance = [&](const Vec3& n) {
    return plane_distance<FloatLanes>(n[rp.kx], n[rp.ky], n[rp.kz], a[rp.kx], a[rp.ky], a[rp.kz], rp.sx, rp.sy,
                                      rp.sz, az, bz, cz);
  };
  float tt = distance(tri.normal());
  // 0 / 0: a sliver whose float normal cancels to zero, or a zero or NaN direction. The normal
  // in double decides the sliver (SIMD kernels send these lanes here).
  if (tt != tt) {
    const DVec3 d0(tri.v0);
    tt = distance(to_float(cross(DVec3(tri.v1) - d0, DVec3(tri.v2) - d0)));
  }
  if (!(tt >= tmin && tt <= tmax)) return false;
  t = tt;
  u = ev / det;
  v = ew / det;
  return true;
}

/// gamma(n) = n eps / (1 - n eps), eps = 2^-24 (half float's ulp of 1): the relative error
/// bound of n float operations (Higham; pbrt-v3 sec. 3.9.1).
constexpr float float_gamma(int n) {
  constexpr float eps = 0.5f * std::numeric_limits<float>::epsilon();
  return float(n) * eps / (1.0f - float(n) * eps);
}
/// The slab test's far-distance scale, 1 + 2 gamma(3) (Ize 2013, sec. 3): every box kernel
/// (scalar and SIMD) must use this one value to cull exactly the same boxes.
inline constexpr float kSlabFarScale = 1.0f + 2.0f * float_gamma(3);

/// Robust slab test (Ize, "Robust BVH Ray Traversal", JCGT 2013): the far distance is
/// scaled up by 1 + 2 gamma(3) so that rounding never culls a box the ray touches at t >= 0
/// (a negative far distance moves away from zero: bvh's intersect_box_robust mirrors it for
/// its widened tmin; DACRT's SIMD kernels repeat this one exactly). The near
/// and far planes of each axis are chosen by the sign of the reciprocal direction, so a zero
/// direction component (+-0, reciprocal +-inf) gives -inf / +inf for a ray inside the slab,
/// and NaN (0 * inf) for a ray lying exactly on one of its planes; the operand order of the
/// comparisons below ignores NaN, which leaves that axis unconstrained: conservative.
/// Returns the entry distance in tnear_out and the exit distance (clipped to tmax) in tfar_out.
inline bool intersect_box(const Vec3& org, const Vec3& inv_dir, const Bounds3& box, float tmin,
                          float tmax, float& tnear_out, float& tfar_out) {
  float tnear = tmin, tfar = tmax;
  for (int axis = 0; axis < 3; ++axis) {
    const bool negative = std::signbit(inv_dir[axis]);
    const float t0 = ((negative ? box.hi : box.lo)[axis] - org[axis]) * inv_dir[axis];
    const float t1 = ((negative ? box.lo : box.hi)[axis] - org[axis]) * inv_dir[axis] * kSlabFarScale;
    tnear = t0 > tnear ? t0 : tnear;  // NaN t0 keeps tnear
    tfar = t1 < tfar ? t1 : tfar;     // NaN t1 keeps tfar
  }
  tnear_out = tnear;
  tfar_out = tfar;
  return tnear <= tfar;
}
/// As above, the entry distance only.
inline bool intersect_box(const Vec3& org, const Vec3& inv_dir, const Bounds3& box, float tmin,
                          float tmax, float& tnear_out) {
  float tfar;
  return intersect_box(org, inv_dir, box, tmin, tmax, tnear_out, tfar);
}

}  // namespace rayscout
