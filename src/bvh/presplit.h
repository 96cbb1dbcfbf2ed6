// Triangle pre-splitting (private): several tight boxes for large triangles before the build.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "rayscout/bvh/bvh_build_config.h"
#include "rayscout/core/bounds3.h"
#include "rayscout/core/triangle.h"

namespace rayscout::detail {

/// Boxes to build over: ref_tri[i] is the triangle whose part inside boxes[i] the reference
/// stands for. Without splitting, one reference per triangle with its full box.
struct PrimReferences {
  std::vector<Bounds3> boxes;
  std::vector<uint32_t> ref_tri;
};

/// Karras and Aila, "Fast parallel construction of high-quality bounding volume hierarchies"
/// (HPG 2013), sec. 3: gives about budget * tris.size() extra references to the triangles whose
/// box wastes the most area (priority (A_box - A_tri)^0.3), and splits each along the coarsest
/// plane of a global power-of-two grid over the scene, clipping the triangle so every piece
/// box is tight. Every point of a triangle stays inside one of its boxes (clip points are
/// padded outward). budget = 0 gives one reference per triangle. A triangle gets at most
/// max_pieces references (clamped to [1, kBvhMaxPresplitPieces]).
PrimReferences presplit_triangles(std::span<const Triangle> tris, float budget, int max_pieces);

/// Where each triangle's references start when triangle i gets 1 + min(max_extra,
/// floor(priority[i] * scale)) of them (max_extra < 2^32): triangle i's are offset[i] ..
/// offset[i + 1] - 1, and offset[priority.size()] is their total. Throws InputError, as the
/// builder does, for a total of 2^27 or more, before anything is allocated.
std::vector<uint32_t> reference_offsets(std::span<const float> priority, double scale, double max_extra);

}  // namespace rayscout::detail
