// ShaftGrid: the voxel grid and cube-map direction grid that classify rays into shafts.
#pragma once

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "rayscout/core/bounds3.h"
#include "rayscout/core/ray.h"

namespace rayscout {

/// Where a ray falls: its origin voxel and its direction cell (paper sec. 4.1: shaft id =
/// voxel x/y/z + cube-map face + u/v).
struct ShaftCoord {
  uint32_t voxel = 0;  ///< x + res_x (y + res_y z)
  uint32_t cell = 0;   ///< (face d + v) d + u, face = 2 axis + (direction negative)
};

/// A regular voxel grid over a box (resolution per axis, near-cubical voxels) times a cube
/// map of 6 d x d direction cells. Classification of a ray (Hendrich et al. 2019, sec. 4.1):
/// - the origin voxel when the origin lies in the box; else the ray is clipped to the box
///   (in double) and classified at its entry point, since no geometry lies before it;
/// - no shaft (the caller starts at the root) for non-finite input, a zero direction or one
///   whose largest component is subnormal (its reciprocal is infinite),
///   tmin < 0, a ray missing the box, or an origin farther than kFarFactor box diagonals
///   from the box (there the triangle test's rounding could exceed the shafts' padding).
class ShaftGrid {
 public:
  /// Origins farther than this many box diagonals from the box are not classified.
  static constexpr double kFarFactor = 32.0;

  ShaftGrid() = default;
  /// Grid over box with res[a] voxels on axis a and d x d cells per cube face.
  ShaftGrid(const Bounds3& box, std::array<int, 3> res, int dir_res);
  /// Near-cubical per-axis resolution with about `voxels` voxels over box (each >= 1; a flat
  /// axis gets 1).
  static std::array<int, 3> cubical_resolution(const Bounds3& box, double voxels);

  const Bounds3& box() const { return box_; }
  const std::array<int, 3>& res() const { return res_; }
  int dir_res() const { return dir_res_; }
  size_t voxel_count() const { return size_t(res_[0]) * res_[1] * res_[2]; }
  uint32_t cells_per_voxel() const { return uint32_t(6 * dir_res_ * dir_res_); }

  /// Edge lengths of a voxel, (box.hi - box.lo) / res per axis.
  const Vec3& voxel_size() const { return size_; }
  /// Box of a voxel (exact grid planes lo + i * size, the last one ends at box.hi).
  Bounds3 voxel_box(uint32_t voxel) const;
  /// Layer along `axis` (0..res[axis]-1, clamped) of the voxels holding coordinate p; the
  /// layers of a box's lo and hi bound the voxels it meets. A flat axis has one layer.
  int layer(float p, int axis) const {
    if (!(size_[axis] > 0.0f)) return 0;
    return std::clamp(int(std::floor((p - box_.lo[axis]) / size_[axis])), 0, res_[axis] - 1);
  }
  /// Voxel of integer coordinates (int arithmetic: below 2^31 voxels, which every grid a
  /// ShaftCollection builds is, as it refuses 2^32 shafts).
  uint32_t voxel_id(int x, int y, int z) const { return uint32_t(x + res_[0] * (y + res_[1] * z)); }
  /// The x, y, z of a voxel id (voxel_id's inverse).
  std::array<int, 3> voxel_coords(uint32_t voxel) const {
    return {int(voxel % uint32_t(res_[0])), int((voxel / uint32_t(res_[0])) % uint32_t(res_[1])),
            int(voxel / (uint32_t(res_[0]) * uint32_t(res_[1])))};
  }
  /// A cube face's u and v axes: the two after its axis, in cyclic order.
  static std::array<int, 2> face_axes(int axis) {
    const int u = axis == 2 ? 0 : axis + 1;
    return {u, u == 2 ? 0 : u + 1};
  }
  /// The block of voxels a box meets: its lo and hi layers on each axis.
  struct VoxelBlock {
    std::array<int, 3> lo, hi;
    /// Layers beyond the first, summed over the axes (0: one voxel).
    int extra_layers() const { return (hi[0] - lo[0]) + (hi[1] - lo[1]) + (hi[2] - lo[2]); }
  };
  VoxelBlock block(const Bounds3& b) const {
    return {{layer(b.lo.x, 0), layer(b.lo.y, 1), layer(b.lo.z, 2)}, {layer(b.hi.x, 0), layer(b.hi.y, 1), layer(b.hi.z, 2)}};
  }
  /// Calls visit(voxel id) for every voxel of the block, x fastest.
  template <class Visit>
  void for_each_voxel(const VoxelBlock& k, Visit visit) const {
    for (int z = k.lo[2]; z <= k.hi[2]; ++z)
      for (int y = k.lo[1]; y <= k.hi[1]; ++y)
        for (int x = k.lo[0]; x <= k.hi[0]; ++x) visit(voxel_id(x, y, z));
  }
  /// Direction cell of a non-zero finite direction.
  uint32_t dir_cell(const Vec3& dir) const {
    const Vec3 a = abs(dir);
    const int axis = max_axis(a);
    const auto [ua, va] = face_axes(axis);
    const float inv = 1.0f / a[axis];
    const int face = 2 * axis + (dir[axis] < 0.0f ? 1 : 0);
    return uint32_t((face * dir_res_ + cell_index(dir[va] * inv)) * dir_res_ + cell_index(dir[ua] * inv));
  }
  /// Classifies a ray; false = no shaft (start at the root), see the class comment.
  bool classify(const Ray& ray, ShaftCoord& out) const {
    if (!(ray.tmin >= 0.0f)) return false;
    if (!(ray.org.x >= box_.lo.x && ray.org.y >= box_.lo.y && ray.org.z >= box_.lo.z &&
          ray.org.x <= box_.hi.x && ray.org.y <= box_.hi.y && ray.org.z <= box_.hi.z))
      return classify_outside(ray, out);
    if (!(max_component(abs(ray.dir)) >= FLT_MIN) || !is_finite(ray.dir)) return false;
    out.voxel = voxel_id(axis_index(ray.org.x, 0), axis_index(ray.org.y, 1), axis_index(ray.org.z, 2));
    out.cell = dir_cell(ray.dir);
    return true;
  }

  /// The cone of a direction cell: its face axis, sign (+1/-1) and [u0,u1] x [v0,v1] in the
  /// face's coordinates (u along axis+1, v along axis+2, both divided by |dir[axis]|).
  struct CellRange {
    int axis, sign;
    double u0, u1, v0, v1;
  };
  CellRange cell_range(uint32_t cell) const;
  /// Direction (not normalised) of face coordinates (u, v) in the cell's face.
  static Vec3 face_direction(const CellRange& c, double u, double v);

 private:
  int cell_index(float u) const {
    const int i = int((u + 1.0f) * 0.5f * float(dir_res_));
    return i < 0 ? 0 : (i >= dir_res_ ? dir_res_ - 1 : i);
  }
  int axis_index(float p, int axis) const {
    const int i = int((p - box_.lo[axis]) * inv_size_[axis]);
    return i < 0 ? 0 : (i >= res_[axis] ? res_[axis] - 1 : i);
  }
  bool classify_outside(const Ray& ray, ShaftCoord& out) const;

  Bounds3 box_{Vec3{0.0f}, Vec3{1.0f}};
  std::array<int, 3> res_{1, 1, 1};
  int dir_res_ = 1;
  Vec3 size_{1.0f}, inv_size_{1.0f};
  double diagonal_ = 1.0;
};

}  // namespace rayscout
