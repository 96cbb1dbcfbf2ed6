// SceneBuilder: assembles meshes into a Scene.
#include "scene_builder.h"

#include <algorithm>

#include "rayscout/core/input_error.h"
#include "text_parse.h"

namespace rayscout::detail {

void SceneBuilder::reserve(size_t triangles) {
  scene_.triangles.reserve(triangles);
  scene_.material_ids.reserve(triangles);
}

uint32_t SceneBuilder::intern(const Material& m) {
  if (auto i = find(m.name)) return *i;
  return define(m);
}

uint32_t SceneBuilder::define(const Material& m) {
  if (auto i = find(m.name)) {
    scene_.materials[*i] = m;
    return *i;
  }
  const uint32_t i = uint32_t(scene_.materials.size());
  scene_.materials.push_back(m);
  by_name_.emplace(m.name, i);
  return i;
}

std::optional<uint32_t> SceneBuilder::find(const std::string& name) const {
  auto it = by_name_.find(name);
  if (it == by_name_.end()) return std::nullopt;
  return it->second;
}

namespace {
bool same_values(const Material& a, const Material& b) {
  return a.type == b.type && a.diffuse == b.diffuse && a.specular == b.specular && a.exponent == b.exponent &&
         a.emission == b.emission;
}
}  // namespace

std::vector<uint32_t> SceneBuilder::intern_all(const Mesh& mesh, const std::string& source,
                                               std::vector<std::string>* warnings) {
  std::vector<uint32_t> map;
  map.reserve(mesh.materials.size());
  for (const auto& m : mesh.materials) {
    const auto existing = find(m.name);
    if (existing && warnings && !same_values(scene_.materials[*existing], m))
      warnings->push_back(printable(source + ": material '" + m.name +
                                    "' differs from an earlier definition of that name; the first one is used"));
    map.push_back(existing ? *existing : define(m));
  }
  return map;
}

namespace {

// The readers reject non-finite coordinates, but a shape's corners are sums (a box from -3e38 to
// 3e38 is infinitely wide), a transform may overflow, and other importers may not check. Finite is
// not enough: the watertight ray-triangle test multiplies three coordinate differences (its scaled
// t), which overflows float beyond ~7e12 (wrong hits, t = inf), and the renderer squares distances
// (light falloff, the scene diagonal). So every vertex must lie within kMaxCoordinate.
void check_vertices(const std::vector<Vec3>& pos, bool transformed, const std::string& source) {
  for (size_t i = 0; i < pos.size(); ++i) {
    const Vec3& p = pos[i];
    if (is_finite(p) && max_component(abs(p)) <= kMaxCoordinate) continue;
    const std::string vertex = "vertex " + std::to_string(i);
    if (!is_finite(p))
      throw InputError(source + (transformed ? ": the transform makes " + vertex + " non-finite"
                                             : ": " + vertex + " is not finite (beyond float range)"));
    throw InputError(source + ": " + vertex + (transformed ? " (transformed)" : "") + " at (" + format_number(p.x) + ", " +
                     format_number(p.y) + ", " + format_number(p.z) + ") " + std::string(kBeyondMaxCoordinate));
  }
}

}  // namespace

void SceneBuilder::add(const Mesh& mesh, const Transform& xf, const std::vector<uint32_t>& material_map,
                       const std::string& source) {
  const bool identity = xf.is_identity();
  std::vector<Vec3> moved;
  if (!identity) {
    moved.reserve(mesh.positions.size());
    for (size_t i = 0; i < mesh.positions.size(); ++i) moved.push_back(xf.apply_point(mesh.positions[i]));
  }
  const std::vector<Vec3>& pos = identity ? mesh.positions : moved;
  check_vertices(pos, !identity, source);
  // Grow geometrically: an exact reserve per mesh would copy everything for every mesh added.
  const size_t need = scene_.triangles.size() + mesh.faces.size();
  if (need > scene_.triangles.capacity()) {
    scene_.triangles.reserve(std::max(need, 2 * scene_.triangles.capacity()));
    scene_.material_ids.reserve(std::max(need, 2 * scene_.material_ids.capacity()));
  }
  const bool mirrored = !identity && xf.determinant() < 0.0;
  size_t dropped = 0;
  for (size_t f = 0; f < mesh.faces.size(); ++f) {
    const auto c = corners_after(mesh.faces[f], mirrored);
    Triangle t{pos[c[0]], pos[c[1]], pos[c[2]]};
    const Vec3 n = t.normal();
    if (n.x == 0.0f && n.y == 0.0f && n.z == 0.0f) {
      ++dropped;
      continue;
    }
    scene_.triangles.push_back(t);
    scene_.material_ids.push_back(material_map[mesh.face_materials[f]]);
  }
  // A mesh that lost every face is an error, not a warning: a scene file's area light or shape
  // would vanish (and the scene get a point light instead).
  if (dropped > 0 && dropped == mesh.faces.size()) {
    const std::string all = dropped == 1 ? "its only triangle has" : "all " + std::to_string(dropped) + " triangles have";
    throw InputError(source + ": " + all + " zero area (repeated indices, collinear vertices, or a transform that flattens them)");
  }
  if (dropped)
    scene_.warnings.push_back(source + ": dropped " + std::to_string(dropped) + " degenerate (zero-area) triangle" +
                              (dropped == 1 ? "" : "s"));
}

void SceneBuilder::finish(const std::string& source_name) {
  if (scene_.triangles.empty()) throw InputError(source_name + ": no triangles (empty scene)");
  if (const float diagonal = length(scene_.bounds().diagonal()); diagonal < kMinDiagonal) {
    throw InputError(source_name + ": the scene is only " + format_number(diagonal) +
                     " across (its bounds' diagonal); below 1e-9 the ray-triangle test's products of three "
                     "coordinates underflow float: scale the scene up");
  }
  scene_.emissive_triangles.clear();
  for (uint32_t i = 0; i < scene_.triangles.size(); ++i)
    if (scene_.material_of(i).emissive()) scene_.emissive_triangles.push_back(i);
}

}  // namespace rayscout::detail
