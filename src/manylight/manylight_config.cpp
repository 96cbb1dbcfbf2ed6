// Names of the visibility modes.
#include "rayscout/manylight/manylight_config.h"

#include "rayscout/core/input_error.h"

namespace rayscout {

VisibilityMode parse_visibility_mode(const std::string& name) {
  for (const auto& [mode_name, mode] : kVisibilityModes)
    if (name == mode_name) return mode;
  std::string known;
  for (const auto& [mode_name, mode] : kVisibilityModes) known += (known.empty() ? "" : ", ") + std::string(mode_name);
  throw InputError("--visibility: unknown mode '" + name + "' (known: " + known + ")");
}

std::string to_string(VisibilityMode mode) {
  for (const auto& [name, named_mode] : kVisibilityModes)
    if (mode == named_mode) return name;
  return "?";
}

}  // namespace rayscout
