// load_scene / resolve_scene: dispatch between JSON scene files, bare meshes and the built-in scene.
#include "rayscout/core/file_extension.h"
#include "rayscout/scene/load_scene.h"

#include "json_scene.h"
#include "rayscout/scene/mesh.h"
#include "scene_builder.h"
#include "text_parse.h"

namespace rayscout {

Scene load_scene(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError(detail::display_name(path) + ": is a directory, not a scene or mesh file");
  const std::string ext = lower_extension(path);
  if (ext == ".json") return detail::load_json_scene(path);

  Mesh mesh = read_mesh(path);
  Scene scene;
  detail::SceneBuilder builder(scene);
  scene.warnings = std::move(mesh.warnings);
  builder.add(mesh, Transform{}, builder.intern_all(mesh), detail::display_name(path));
  builder.finish(detail::display_name(path));
  const Bounds3 b = scene.bounds();
  scene.camera = framing_camera(b);
  // As a JSON scene without lights: a mesh with emitters is lit by them alone.
  if (scene.emissive_triangles.empty()) scene.point_lights.push_back(framing_light(b, scene.camera));
  return scene;
}

Scene resolve_scene(const std::string& arg) {
  if (arg.empty() || arg == "cornell") return default_scene();
  return load_scene(arg);
}

}  // namespace rayscout
