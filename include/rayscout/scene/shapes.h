// Built-in shapes for scene files: quads and boxes as small meshes.
#pragma once

#include "rayscout/scene/mesh.h"

namespace rayscout {

/// A parallelogram corner, corner + e1, corner + e1 + e2, corner + e2: two triangles
/// (corner, c+e1, c+e1+e2) and (corner, c+e1+e2, c+e2); normal e1 x e2.
Mesh make_quad(const Vec3& corner, const Vec3& edge1, const Vec3& edge2);

/// A rectangle of width x height centred at center, facing normal; `up` (projected onto the
/// plane) gives the height direction. Uses make_quad, so the normal is edge1 x edge2.
Mesh make_quad_centered(const Vec3& center, const Vec3& normal, float width, float height,
                        const Vec3& up = Vec3(0, 1, 0));

/// An axis-aligned box [lo, hi]: 12 triangles, outward normals, faces in the order
/// -x, +x, -y, +y, -z, +z. with_bottom = false leaves out the -y face (10 triangles).
Mesh make_box(const Vec3& lo, const Vec3& hi, bool with_bottom = true);

}  // namespace rayscout
