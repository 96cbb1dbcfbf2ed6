// Shaft selection (private): which shafts of a grid get candidate lists (paper sec. 4.4).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "rayscout/core/ray.h"
#include "rayscout/core/triangle.h"
#include "rayscout/shafts/shaft_config.h"
#include "rayscout/shafts/shaft_grid.h"

namespace rayscout::detail {

/// Which shafts get lists (paper sec. 4.4): voxel flags, and per shaft flags for Camera
/// (empty = every cell of a listed voxel: Occupied, CameraVoxels).
struct Selection {
  std::vector<uint8_t> voxel_listed, shaft_selected;
  size_t shafts = 0;
};

/// Occupied: every cell of every voxel a triangle touches; Camera: the most used shafts of
/// the pre-pass rays sample_rays until config.coverage of them is covered; CameraVoxels: the
/// same over the voxels the rays start in (or enter the grid at), with every cell listed.
Selection select_shafts(const ShaftGrid& grid, std::span<const Triangle> tris, const RayBatch& sample_rays,
                        const ShaftConfig& config);

}  // namespace rayscout::detail
