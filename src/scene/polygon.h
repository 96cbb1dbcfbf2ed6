// Polygons of the OBJ and PLY readers: fan-triangulated while read, ear-clipped afterwards where
// the fan would cover area outside the polygon (a concave polygon).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "rayscout/scene/mesh.h"

namespace rayscout::detail {

/// Polygons with more vertices than this keep their fan even when it leaves them: ear clipping
/// takes up to n^3 steps, and real concave faces have a few dozen vertices.
inline constexpr size_t kMaxEarClipVertices = 1024;

/// One polygon of n >= 4 vertices v0 ... v(n-1), stored in Mesh::faces from `first` as its fan
/// (v0 v1 v2), (v0 v2 v3), ..., (v0 v(n-2) v(n-1)).
struct FannedPolygon {
  size_t first;
  uint32_t vertices;
};

/// Appends the fan of polygon `poly` (>= 3 vertex indices) with material `material`, and records
/// it in `polygons` when it has more than 3 vertices.
void add_polygon(const std::vector<uint32_t>& poly, uint32_t material, Mesh& mesh, std::vector<FannedPolygon>& polygons);

/// Replaces the fan of each polygon whose fan covers area outside it (a fan triangle turned the
/// other way than the polygon, in the plane of its Newell normal) by an ear-clipping triangulation
/// (same triangle count, same place in Mesh::faces, the polygon's winding kept). Convex polygons,
/// and concave ones that their first vertex sees whole, keep the fan. Call once every position is
/// read (OBJ indices may point forward). Returns how many concave polygons kept their fan for having
/// more than kMaxEarClipVertices vertices.
size_t ear_clip_concave(Mesh& mesh, const std::vector<FannedPolygon>& polygons);

/// The warning for `kept` (> 0) concave polygons of `file` that ear_clip_concave left as fans.
std::string concave_fans_kept(const std::string& file, size_t kept);

}  // namespace rayscout::detail
