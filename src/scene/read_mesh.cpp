// read_mesh: picks the reader by file extension.
#include <string>

#include "rayscout/core/file_extension.h"
#include "rayscout/scene/mesh.h"
#include "text_parse.h"

namespace rayscout {

Mesh read_mesh(const std::filesystem::path& path) {
  if (const std::string why = detail::not_a_file(path); !why.empty())
    throw InputError(detail::display_name(path) + ": " + why);
  const std::string ext = lower_extension(path);
  if (ext == ".obj") return read_obj(path);
  if (ext == ".ply") return read_ply(path);
  if (ext == ".gltf" || ext == ".glb") return read_gltf(path);
  if (ext.empty())
    throw InputError(detail::display_name(path) +
                     ": no file extension to tell the format by (expected .obj, .ply, .gltf, .glb or a .json scene)");
  if (ext == ".json")
    throw InputError(detail::display_name(path) +
                     ": a .json scene cannot be used as a mesh (meshes are .obj, .ply, .gltf or .glb)");
  throw InputError(printable(detail::display_name(path) + ": unknown mesh format '" + ext +
                                     "' (expected .obj, .ply, .gltf, .glb or a .json scene)"));
}

}  // namespace rayscout
