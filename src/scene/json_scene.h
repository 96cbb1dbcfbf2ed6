// JSON scene files (schema in docs/scene-format.md).
#pragma once

#include <filesystem>

#include "rayscout/scene/scene.h"

namespace rayscout::detail {

/// Loads a .json scene file; errors name the file and the JSON field path.
Scene load_json_scene(const std::filesystem::path& path);

}  // namespace rayscout::detail
