// Surface origins of sample rays (private): the triangles' area inside each voxel, so that a
// shaft's sample rays can start where the rays that use its list start, on surfaces.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "rayscout/core/triangle.h"
#include "rayscout/shafts/shaft_grid.h"

namespace rayscout::detail {

/// The triangles clipped to each of a set of voxels, as pieces sampled uniformly by area.
/// Secondary rays (shadow, AO, diffuse, path) start on surfaces; origins uniform in the voxel
/// volume also start behind and inside the surfaces (under a floor, inside a wall) and hit
/// them at once, so they see less of the scene than the rays the list serves.
class VoxelSurfaces {
 public:
  VoxelSurfaces() = default;
  /// The surfaces inside every voxel of `voxels` (any order, no duplicates).
  VoxelSurfaces(const ShaftGrid& grid, std::span<const Triangle> tris, std::span<const uint32_t> voxels);

  /// A point uniform by area on the surfaces inside voxel v, from rnd[0] (which piece) and
  /// rnd[1], rnd[2] (where on it), each in [0, 1); false when v holds no surface or is not one
  /// of the constructor's voxels.
  bool sample(uint32_t voxel, const float rnd[3], Vec3& p) const;
  /// tmin of a sample ray from a surface point: its own triangle must not count as its hit.
  float epsilon() const { return epsilon_; }

 private:
  /// Index of voxel in voxels_, or -1.
  int64_t slot(uint32_t voxel) const;

  struct Piece {
    Vec3 v0, e1, e2;
  };
  std::vector<uint32_t> voxels_;  ///< sorted voxel ids
  std::vector<uint32_t> begin_;   ///< pieces of voxels_[k]: [begin_[k], begin_[k + 1])
  std::vector<Piece> pieces_;
  std::vector<float> cdf_;  ///< per piece, the voxel's area up to and including it, over the voxel's area
  float epsilon_ = 0.0f;
};

}  // namespace rayscout::detail
