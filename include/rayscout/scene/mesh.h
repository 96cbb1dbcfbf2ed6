// Mesh: an indexed triangle mesh as read from one file, before it is placed in a scene.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "rayscout/scene/scene.h"

namespace rayscout {

/// Triangles of one mesh file in file order (polygons fan-triangulated in place:
/// v0 v1 v2, v0 v2 v3, ..., or ear-clipped where the fan leaves a concave polygon), with the
/// materials its faces use (from the MTL for OBJ).
struct Mesh {
  std::vector<Vec3> positions;
  std::vector<std::array<uint32_t, 3>> faces;  ///< indices into positions
  std::vector<uint32_t> face_materials;        ///< per face, index into materials
  std::vector<Material> materials;             ///< names are unique within the mesh
  std::vector<std::string> warnings;           ///< e.g. a missing .mtl, an unknown usemtl
};

/// Reads a mesh file by extension: .obj (+ .mtl), .ply, .gltf/.glb (assimp).
/// Throws InputError "file:line: what" for malformed input (binary PLY: element and byte
/// offset instead of a line), out-of-range indices, non-finite coordinates or no faces.
Mesh read_mesh(const std::filesystem::path& path);

/// Wavefront OBJ with its MTL libraries (material mapping in docs/scene-format.md).
Mesh read_obj(const std::filesystem::path& path);
/// PLY, ascii or binary little/big endian: vertex x y z and face vertex_indices lists.
Mesh read_ply(const std::filesystem::path& path);
/// glTF 2.0 (.gltf/.glb) through assimp; triangles of every mesh node, node transforms applied,
/// emission scaled by KHR_materials_emissive_strength, only materials some triangle uses.
Mesh read_gltf(const std::filesystem::path& path);

/// Parses an MTL file into materials (appended to out, replacing same-named ones). A material
/// that would reflect more than it receives is scaled down (conserve_energy) with a warning
/// "file:line: material 'name': ..." appended to warnings when given.
void read_mtl(const std::filesystem::path& path, std::vector<Material>& out,
              std::vector<std::string>* warnings = nullptr);

/// Energy conservation for materials from files rayscout does not control (MTL, glTF): when
/// the largest channel of the reflectance the material uses, max(Kd + Ks) (Ks alone for a
/// mirror, which has no diffuse lobe), exceeds 1, scales diffuse and specular by 1 / that
/// maximum (as Mitsuba does) and returns the maximum; otherwise returns it and changes nothing.
float conserve_energy(Material& m);

/// conserve_energy(m), and when it scaled m, the warning "<where>: material '<name>': Kd + Ks
/// reaches <max> in a channel (...); Kd and Ks scaled by 1/<max>" (empty when m was kept).
std::string conserve_energy_with_warning(Material& m, const std::string& where);

/// Maps MTL values to a Material: Ke -> emission, Kd -> diffuse; with Ks > 0, illum 3/5/7
/// or Ns >= 1000 -> Mirror, else Glossy with exponent Ns; Ks = 0 -> Diffuse.
Material material_from_mtl(std::string name, const Vec3& kd, const Vec3& ks, float ns, int illum,
                           const Vec3& ke);

}  // namespace rayscout
