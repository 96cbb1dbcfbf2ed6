// Shaft: the conservative geometry of one shaft (voxel x direction cell), used only while
// building candidate lists.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

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
/// edge x box axis). In exact arithmetic the test is exact; it runs in double on a voxel
/// padded by pad_space and a cell padded by pad_dir, so rounding in classification, in the
/// entry-point clip and in the watertight triangle test can never cull reachable geometry.
class Shaft {
 public:
  /// Relative padding of the voxel (times the grid box diagonal) and of the cell (in face
  /// coordinates u, v in [-1, 1]).
  static constexpr double kPadSpace = 1e-4, kPadDir = 1e-4;

  Shaft(const ShaftGrid& grid, ShaftCoord coord);

  /// Conservative: false only when no ray of the shaft can reach any point of b.
  bool overlaps(const Bounds3& b) const {
    if (b.empty()) return false;
    // Axes one at a time: the first (voxel faces) reject most boxes, so the early exit beats
    // a vectorised test of all axes (measured).
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
  /// Ray i of a uniform random sample: origin uniform in the (unpadded) voxel, direction
  /// uniform in the cell's face coordinates. rnd holds 5 numbers in [0, 1).
  Ray sample_ray(const float rnd[5]) const;
  /// Direction of the cell centre (orders children near-first, Algorithm 1 lines 9-14).
  const Vec3& center_dir() const { return center_dir_; }
  /// Number of separating axes kept (for tests).
  size_t axis_count() const { return size_t(axis_count_); }
  /// The (unpadded) voxel box; sample ray origins lie in it.
  const Bounds3& voxel() const { return voxel_; }

 private:
  std::array<double, 3> vlo_{}, vhi_{};
  /// n with cone . n >= 0; at most 3 faces + 12 bevels + 4 sides (fixed storage: one shaft
  /// is made per list, so heap allocations showed in the build profile).
  std::array<std::array<double, 3>, 19> axes_{};
  int axis_count_ = 0;
  Bounds3 voxel_;
  ShaftGrid::CellRange cell_{};
  Vec3 center_dir_;
};

}  // namespace rayscout
