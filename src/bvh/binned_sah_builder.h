// Binned SAH builder (private): primitive boxes in, a Bvh2 node array out.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "rayscout/bvh/bvh_build_config.h"
#include "rayscout/bvh/bvh2.h"

namespace rayscout::detail {

/// Throws InputError unless count is below 2^27, the most primitives a build takes: the wide
/// BVH's leaf references address 2^27 slots (WideRef::kMaxFirst), and the Bvh2 shares the limit.
void check_primitive_count(uint64_t count);

/// Builds a binary BVH over primitives known only by their boxes, binned by box centre
/// (binned SAH, Wald 2007, all three axes; parallel binning of large nodes and
/// task-parallel recursion with oneTBB). Fills nodes (root first, siblings adjacent,
/// depth-first order) and prim_ids; returns the depth. The result does not depend on the
/// thread count. Throws InputError for a config out of range.
int build_binned_sah(std::span<const Bounds3> boxes, const BvhBuildConfig& config,
                     std::vector<Bvh2Node>& nodes, std::vector<uint32_t>& prim_ids);

}  // namespace rayscout::detail
