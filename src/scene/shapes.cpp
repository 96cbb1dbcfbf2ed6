// Quads and boxes as small meshes (one default material).
#include "rayscout/scene/shapes.h"

namespace rayscout {
namespace {

Mesh single_material_mesh() {
  Mesh m;
  m.materials.push_back(Material{.name = "default"});
  return m;
}

void add_quad(Mesh& m, const Vec3& c, const Vec3& e1, const Vec3& e2) {
  const uint32_t b = uint32_t(m.positions.size());
  m.positions.insert(m.positions.end(), {c, c + e1, c + e1 + e2, c + e2});
  m.faces.push_back({b, b + 1, b + 2});
  m.faces.push_back({b, b + 2, b + 3});
  m.face_materials.insert(m.face_materials.end(), 2, 0u);
}

}  // namespace

Mesh make_quad(const Vec3& corner, const Vec3& edge1, const Vec3& edge2) {
  Mesh m = single_material_mesh();
  add_quad(m, corner, edge1, edge2);
  return m;
}

Mesh make_quad_centered(const Vec3& center, const Vec3& normal, float width, float height, const Vec3& up) {
  // Scaled to its largest component first: the squared length of a tiny (1e-30) or huge
  // normal under- or overflows float, and only the direction matters.
  const Vec3 n = normalize(normal / max_component(abs(normal)));
  Vec3 v = up - n * dot(up, n);
  // Parallel when the sine of their angle is below 1e-6, as for the camera's up, whatever |up|.
  if (length(v) < 1e-6f * length(up)) {  // pick any perpendicular direction
    v = std::abs(n.x) < 0.9f ? cross(n, Vec3(1, 0, 0)) : cross(n, Vec3(0, 1, 0));
  }
  v = normalize(v);
  const Vec3 u = cross(v, n);  // u x v = n, so the quad faces n
  const Vec3 e1 = u * width, e2 = v * height;
  return make_quad(center - e1 * 0.5f - e2 * 0.5f, e1, e2);
}

Mesh make_box(const Vec3& lo, const Vec3& hi, bool with_bottom) {
  Mesh m = single_material_mesh();
  const Vec3 d = hi - lo;
  const Vec3 ex(d.x, 0, 0), ey(0, d.y, 0), ez(0, 0, d.z);
  add_quad(m, lo, ez, ey);                       // -x
  add_quad(m, lo + ex, ey, ez);                  // +x
  if (with_bottom) add_quad(m, lo, ex, ez);      // -y
  add_quad(m, lo + ey, ez, ex);                  // +y
  add_quad(m, lo, ey, ex);                       // -z
  add_quad(m, lo + ez, ex, ey);                  // +z
  return m;
}

}  // namespace rayscout
