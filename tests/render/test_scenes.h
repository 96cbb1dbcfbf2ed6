// Small scenes with known answers for the renderer tests.
#pragma once

#include <vector>

#include "generated_scenes.h"
#include "rayscout/image/image.h"
#include "rayscout/scene/scene.h"

namespace rayscout::testing {

/// Mean of channel c over the image's pixels.
inline double mean_channel(const Image& img, int c) {
  double s = 0;
  for (const Vec3& p : img.pixels) s += p[c];
  return s / double(img.pixels.size());
}

/// Appends triangles with one new material; returns the material id.
inline uint32_t add_part(Scene& scene, const std::vector<Triangle>& tris, const Material& m) {
  const uint32_t id = uint32_t(scene.materials.size());
  scene.materials.push_back(m);
  for (const Triangle& t : tris) {
    if (m.emissive()) scene.emissive_triangles.push_back(uint32_t(scene.triangles.size()));
    scene.triangles.push_back(t);
    scene.material_ids.push_back(id);
  }
  return id;
}

/// The triangles with their winding reversed (normals flipped).
inline std::vector<Triangle> flipped(std::vector<Triangle> tris) {
  for (Triangle& t : tris) std::swap(t.v1, t.v2);
  return tris;
}

/// A tessellated sphere whose normals point inwards.
inline std::vector<Triangle> inward_sphere(const Vec3& c, float r, int subdivisions) {
  std::vector<Triangle> tris = sphere(c, r, subdivisions);
  for (Triangle& t : tris)
    if (dot(t.normal(), t.centroid() - c) > 0) std::swap(t.v1, t.v2);
  return tris;
}

/// Two triangles: the quad corner, corner + e1, corner + e1 + e2, corner + e2 (normal e1 x e2).
inline std::vector<Triangle> quad(const Vec3& corner, const Vec3& e1, const Vec3& e2) {
  return {{corner, corner + e1, corner + e1 + e2}, {corner, corner + e1 + e2, corner + e2}};
}

/// The 12 triangles of the box [lo, hi], normals pointing inwards.
inline std::vector<Triangle> inward_box(const Vec3& lo, const Vec3& hi) {
  const Vec3 d = hi - lo;
  std::vector<Triangle> t;
  auto add = [&](std::vector<Triangle> q) { t.insert(t.end(), q.begin(), q.end()); };
  add(quad(lo, {d.x, 0, 0}, {0, d.y, 0}));                       // z = lo, normal +z
  add(quad(lo + Vec3{0, 0, d.z}, {0, d.y, 0}, {d.x, 0, 0}));     // z = hi, normal -z
  add(quad(lo, {0, d.y, 0}, {0, 0, d.z}));                       // x = lo, normal +x
  add(quad(lo + Vec3{d.x, 0, 0}, {0, 0, d.z}, {0, d.y, 0}));     // x = hi, normal -x
  add(quad(lo, {0, 0, d.z}, {d.x, 0, 0}));                       // y = lo, normal +y
  add(quad(lo + Vec3{0, d.y, 0}, {d.x, 0, 0}, {0, 0, d.z}));     // y = hi, normal -y
  return t;
}

}  // namespace rayscout::testing
