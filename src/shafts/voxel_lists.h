// VoxelLists (private): one listed voxel's candidate lists between the parallel build
// (shaft_collection.cpp) and packing (shaft_packing.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace rayscout::detail {

/// The lists of one listed voxel before packing: per cell a status and the cell's list,
/// concatenated in data.
struct VoxelLists {
  enum Status : uint8_t { kNoList, kList, kReachesNothing };
  std::vector<Status> status;
  std::vector<uint8_t> len;
  std::vector<uint32_t> begin;  ///< start of the cell's list in data (groups fill data out of cell order)
  std::vector<uint32_t> data;   ///< node indices
  size_t near_retries = 0, retries = 0, fallbacks = 0;  ///< ShaftStats' overflow counters
};

}  // namespace rayscout::detail
