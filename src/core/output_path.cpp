// check_output_path: an output file's folder exists and the path is no directory.
#include "rayscout/core/output_path.h"

#include <fstream>

#include "rayscout/core/input_error.h"

namespace rayscout {

void check_output_path(const std::filesystem::path& path, const std::string& label) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(label + ": is a directory");
  const std::filesystem::path parent = path.parent_path();
  if (!parent.empty() && !std::filesystem::is_directory(parent, ec))
    throw InputError(label + ": folder " + parent.string() + " does not exist");
}

void write_file(const std::filesystem::path& path, std::string_view bytes, const std::string& label) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw InputError(label + ": cannot open " + path.string() + " for writing");
  out.write(bytes.data(), std::streamsize(bytes.size()));
  out.close();
  if (!out) throw InputError(label + ": cannot write " + path.string() + " (" + std::to_string(bytes.size()) + " bytes)");
}

}  // namespace rayscout
