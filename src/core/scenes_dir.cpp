// scenes_dir: resolves RAYSCOUT_SCENES.
#include "rayscout/core/scenes_dir.h"

#include <cstdlib>

namespace rayscout {

std::filesystem::path scenes_dir() {
  if (const char* env = std::getenv("RAYSCOUT_SCENES"); env && *env) return env;
  if (const char* env = std::getenv("RAYSCOUT_DEFAULT_SCENES"); env && *env) return env;
  return RAYSCOUT_DEFAULT_SCENES;
}

std::string scenes_dir_origin() {
  const char* env = std::getenv("RAYSCOUT_SCENES");
  return (env && *env ? "RAYSCOUT_SCENES=" : "RAYSCOUT_SCENES is not set, default ") + scenes_dir().string();
}

std::optional<std::filesystem::path> find_scene_file(const std::string& relative) {
  std::filesystem::path p = scenes_dir() / relative;
  std::error_code ec;
  if (std::filesystem::exists(p, ec)) return p;
  return std::nullopt;
}

}  // namespace rayscout
