// The extension of a file name in lower case: how readers and writers pick a format.
#pragma once

#include <cctype>
#include <filesystem>
#include <string>

namespace rayscout {

/// ".obj", ".gltf", ".png", ... for any case of the name's extension ("" when it has none).
inline std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace rayscout
