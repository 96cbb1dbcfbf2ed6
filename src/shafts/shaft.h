// Shaft (private): the conservative geometry of one shaft (voxel x direction cell), used
// only while building candidate lists.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

#include "rayscout/core/bounds3.h"
#include "rayscout/core/ray.h"
#include "rayscout/shafts/shaft_grid.h"

namespace rayscout {

/// The set of points a ray of the shaft can reach: voxel (+) cone of the direction cell
/// (Minkowski sum), the far end open (Hendrich et al. 2019, sec. 4.2; Arvo & Kirk 1987).
/// A box B overlaps it iff the box B (-) voxel = [B.lo - V.hi, B.hi - V.lo] meets the cone;
/// that is decided by the separating-axis test over the culling planes: the 4 planes of the
/// direction interval (pushed out to the voxel by the Minkowski sum), the voxel's back and
/// outer faces (box axes on which the whole cone is one-signed) and the bevel planes (cone
/// edge x box axis). In exact arithmetic the test is exact. overlaps() runs it in float,
/// overlaps_exact() in double, on a voxel padded by kPadSpace of the diagonal or 4 ulps of
/// the coordinates, whichever is more, and a cell padded by kPadDir. The padding covers
/// rounding in the triangle test and in classification against float voxel planes (an
/// outside ray's entry point, clipped in double, lay 0.027 outside its voxel at y = 1e6 in a
/// review's test); the float test's tolerance tol_ covers only its own rounding (shaft.cpp).
class Shaft {
 public:
  /// Relative padding of the voxel (times the grid box diagonal) and of the cell (in face
  /// coordinates u, v in [-1, 1]).
  static constexpr double kPadSpace = 1e-4, kPadDir = 1e-4;

  Shaft(const ShaftGrid& grid, ShaftCoord coord);
  /// The shaft of `voxel` and any face rectangle `cell` of directions (e.g. the union of
  /// several cells of one face).
  Shaft(const ShaftGrid& grid, uint32_t voxel, const ShaftGrid::CellRange& cell);
  /// Moves the shaft to another voxel of the same grid (the cone, and so the axes, stay):
  /// cheaper than constructing it again.
  void set_voxel(const ShaftGrid& grid, uint32_t voxel);

  /// A box minus the (padded) voxel, B (-) V = [B.lo - V.hi, B.hi - V.lo], in float; the same
  /// for every shaft of one voxel, so a caller testing many shafts computes it once.
  struct BoxDiff {
    float lo[3], hi[3];
  };
  BoxDiff diff(const Bounds3& b) const {
    BoxDiff d;
    for (int k = 0; k < 3; ++k) {
      d.lo[k] = b.lo[k] - fvhi_[k];
      d.hi[k] = b.hi[k] - fvlo_[k];
    }
    return d;
  }
  /// Separating-axis test of every culling plane at once (float, branch-free, vectorised).
  /// Conservative: the support value max n.x over B (-) V is rejected only below -tol, tol
  /// above its float rounding error; the float axes are valid separating axes because the
  /// real cone lies inside the padded one by far more than their rounding (see shaft.cpp).
  /// The axes fill one row of 16 float slots (one AVX-512 register).
  bool overlaps(const BoxDiff& d) const {
#if defined(__AVX512F__)
    const __m512 hx = _mm512_set1_ps(d.hi[0]), lx = _mm512_set1_ps(d.lo[0]);
    const __m512 hy = _mm512_set1_ps(d.hi[1]), ly = _mm512_set1_ps(d.lo[1]);
    const __m512 hz = _mm512_set1_ps(d.hi[2]), lz = _mm512_set1_ps(d.lo[2]);
    // Same operations in the same order as the scalar loop (no contraction).
    __m512 m = _mm512_mul_ps(_mm512_loadu_ps(pos_[0]), hx);
    m = _mm512_add_ps(m, _mm512_mul_ps(_mm512_loadu_ps(neg_[0]), lx));
    m = _mm512_add_ps(m, _mm512_mul_ps(_mm512_loadu_ps(pos_[1]), hy));
    m = _mm512_add_ps(m, _mm512_mul_ps(_mm512_loadu_ps(neg_[1]), ly));
    m = _mm512_add_ps(m, _mm512_mul_ps(_mm512_loadu_ps(pos_[2]), hz));
    m = _mm512_add_ps(m, _mm512_mul_ps(_mm512_loadu_ps(neg_[2]), lz));
    return _mm512_cmp_ps_mask(m, _mm512_set1_ps(-tol_), _CMP_LT_OQ) == 0;
#else
    const float limit = -tol_;
    int separated = 0;  // an integer or-reduction vectorises (a float min does not without fast-math)
    for (int a = 0; a < kAxes; ++a) {
      const float m = pos_[0][a] * d.hi[0] + neg_[0][a] * d.lo[0] + pos_[1][a] * d.hi[1] + neg_[1][a] * d.lo[1] +
                      pos_[2][a] * d.hi[2] + neg_[2][a] * d.lo[2];
      separated |= m < limit ? 1 : 0;
    }
    return separated == 0;
#endif
  }
  /// Axis slots of the float test (unused slots are zero axes, which always pass): room for
  /// the at most 15 distinct culling axes.
  static constexpr int kAxes = 16;
  /// Conservative: false only when no ray of the shaft can reach any point of b.
  bool overlaps(const Bounds3& b) const { return !b.empty() && overlaps(diff(b)); }
  /// Culling axes in use (distinct; for tests).
  int axis_count() const { return axis_count_; }
  /// The exact test in double (reference for tests): same axes, no tolerance.
  bool overlaps_exact(const Bounds3& b) const {
    if (b.empty()) return false;
    for (int a = 0; a < axis_count_; ++a) {
      const auto& n = axes_[size_t(a)];
      double m = 0.0;
      for (int k = 0; k < 3; ++k) {
        const double lo = double(b.lo[k]) - vhi_[k], hi = double(b.hi[k]) - vlo_[k];
        m += n[k] > 0.0 ? hi * n[k] : lo * n[k];
      }
      if (m < 0.0) return false;
    }
    return true;
  }
  /// A ray of a uniform random sample: origin uniform in the (unpadded) voxel, direction
  /// uniform in the cell's face coordinates. rnd holds 5 numbers in [0, 1).
  Ray sample_ray(const float rnd[5]) const { return sample_ray(voxel_, cell_, rnd); }
  /// The same for any voxel box and cell (no shaft needed).
  static Ray sample_ray(const Bounds3& voxel, const ShaftGrid::CellRange& cell, const float rnd[5]);
  /// The direction interval of the shaft.
  const ShaftGrid::CellRange& cell() const { return cell_; }
  /// Direction of the cell centre (orders children near-first, Algorithm 1 lines 9-14).
  const Vec3& center_dir() const { return center_dir_; }
  /// The (unpadded) voxel box; sample ray origins lie in it.
  const Bounds3& voxel() const { return voxel_; }

 private:
  std::array<double, 3> vlo_{}, vhi_{};
  float fvlo_[3] = {}, fvhi_[3] = {};  ///< the padded voxel rounded outward to float
  /// Axes split in positive and negative parts per component: n.x maximised over a box is
  /// pos . hi + neg . lo.
  alignas(64) float pos_[3][kAxes] = {}, neg_[3][kAxes] = {};
  float tol_ = 0.0f;
  /// n with cone . n >= 0, no two alike: at most 3 faces + 12 bevels, as the 4 sides repeat
  /// bevels (fixed storage: shafts are copied per group and voxel, and heap allocations
  /// showed in the build profile).
  std::array<std::array<double, 3>, kAxes> axes_{};
  int axis_count_ = 0;
  Bounds3 voxel_;
  ShaftGrid::CellRange cell_{};
  Vec3 center_dir_;
};

}  // namespace rayscout
