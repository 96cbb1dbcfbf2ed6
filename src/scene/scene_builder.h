// SceneBuilder: assembles meshes into a Scene (material table, transforms, degenerate drops).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "rayscout/scene/mesh.h"
#include "rayscout/scene/transform.h"

namespace rayscout::detail {

/// Largest |coordinate| of a vertex, camera or light: the ray-triangle test's products of three
/// coordinate differences (up to ~2e11 each, times a direction scale <= sqrt 3) stay far below
/// float's 3.4e38, and so do squared distances.
inline constexpr float kMaxCoordinate = 1e11f;

/// The end of every error about a value beyond kMaxCoordinate: "<what> is beyond +-1e11, ...".
inline constexpr std::string_view kBeyondMaxCoordinate =
    "is beyond +-1e11, where the ray-triangle test's products of three coordinates overflow float; scale the scene down";

/// The smallest scene, by the diagonal of its bounds: the ray-triangle test multiplies three
/// coordinate differences, which leave float's normal range (1.2e-38) below ~2e-13; at 1e-14
/// hits came out at t = 0 and BVHs parted from brute force. 1e-9 keeps a margin of 1e-27.
inline constexpr float kMinDiagonal = 1e-9f;

/// A face's corners after a transform: a mirroring one (negative determinant) turns the face
/// inside out, so two corners swap to keep its front (one-sided area lights emit from it)
/// where the author put it, as glTF 2.0 (sec. 3.7.4) asks of nodes with a negative determinant.
inline std::array<uint32_t, 3> corners_after(const std::array<uint32_t, 3>& face, bool mirrored) {
  return mirrored ? std::array<uint32_t, 3>{face[0], face[2], face[1]} : face;
}

/// Appends meshes to a scene in call order, so triangle ids are the load order.
class SceneBuilder {
 public:
  explicit SceneBuilder(Scene& scene) : scene_(scene) {}

  /// Reserves room for this many triangles in total.
  void reserve(size_t triangles);
  /// Index of the material named m.name; adds m when no material has that name yet.
  uint32_t intern(const Material& m);
  /// Adds m, or replaces the material of the same name; returns its index.
  uint32_t define(const Material& m);
  std::optional<uint32_t> find(const std::string& name) const;
  Material& material(uint32_t index) { return scene_.materials[index]; }
  /// The materials defined so far, in definition order.
  const std::vector<Material>& materials() const { return scene_.materials; }

  /// Scene material indices of the mesh's own materials (interned by name). A material
  /// whose name exists with other values keeps the first definition; that adds a warning
  /// naming `source` to `warnings` when given.
  std::vector<uint32_t> intern_all(const Mesh& mesh, const std::string& source = {},
                                   std::vector<std::string>* warnings = nullptr);

  /// Appends the mesh's faces through xf. material_map[i] is the scene material of mesh
  /// material i. Zero-area triangles (after the transform) are dropped and counted under
  /// `source` in the scene's warnings. InputError naming `source` when a transformed vertex is
  /// not finite or beyond kMaxCoordinate, or when every face of a mesh that has some was dropped.
  void add(const Mesh& mesh, const Transform& xf, const std::vector<uint32_t>& material_map,
           const std::string& source);

  /// Fills emissive_triangles; throws InputError "source_name: no triangles (empty scene)" when
  /// empty, or one saying that the scene is too small for float (kMinDiagonal).
  void finish(const std::string& source_name);

 private:
  Scene& scene_;
  std::unordered_map<std::string, uint32_t> by_name_;
};

}  // namespace rayscout::detail
