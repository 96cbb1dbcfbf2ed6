// Scene loading: JSON scene files, bare meshes (OBJ+MTL, PLY, glTF) and the built-in scene.
#pragma once

#include <filesystem>
#include <string>

#include "rayscout/core/input_error.h"
#include "rayscout/scene/scene.h"

namespace rayscout {

/// Loads a scene from a .json scene file (schema in docs/scene-format.md) or a bare mesh
/// (.obj with its .mtl, .ply ascii or binary, .gltf/.glb through assimp). A bare mesh gets a
/// camera framing its bounds and, unless it has emissive triangles, one point light. Triangle
/// ids are the load order (docs/scene-format.md). Throws InputError naming the file and line,
/// or the JSON field path, on bad input. Zero-area triangles are dropped and counted in
/// Scene::warnings; a mesh (or scene-file entry) that loses all of them is an InputError.
Scene load_scene(const std::filesystem::path& path);

/// The built-in Cornell-box-like scene: white floor, ceiling and back wall, red left and
/// green right wall, a short and a tall box, an emissive quad under the ceiling (area light)
/// and a point light just below it; the camera looks in through the open +z side.
/// The box spans [-1, 1] x [0, 2] x [-1, 1].
Scene default_scene();

/// The scene a `--scene` argument names: "" or "cornell" give default_scene(), anything
/// else is a path for load_scene().
Scene resolve_scene(const std::string& arg);

/// The camera given to a bare mesh: looks at the centre of b along -z from where the
/// bounding sphere just fills a vertical field of view of fov_deg degrees (Y up).
Camera framing_camera(const Bounds3& b, float fov_deg = 60.0f);

/// The point light given to a bare mesh: above and behind the camera by a quarter of the
/// bounds' radius, with intensity (d^2, d^2, d^2) W/sr for its distance d to the centre,
/// so the irradiance facing it at the centre is about 1.
PointLight framing_light(const Bounds3& b, const Camera& camera);

}  // namespace rayscout
