// Where the real benchmark scenes live (never inside the project).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace rayscout {

/// The scenes folder: $RAYSCOUT_SCENES, else $RAYSCOUT_DEFAULT_SCENES (which CTest sets),
/// else the build's default, ../shared/scenes beside the source tree.
std::filesystem::path scenes_dir();

/// Where scenes_dir() came from, for messages about missing scenes:
/// "RAYSCOUT_SCENES=/x", or "RAYSCOUT_SCENES is not set, default /y".
std::string scenes_dir_origin();

/// scenes_dir() / relative when that file exists, else nullopt (callers skip with a message).
std::optional<std::filesystem::path> find_scene_file(const std::string& relative);

}  // namespace rayscout
