// Output files: checked for writing before the work (check_output_path), written whole (write_file).
#include "rayscout/core/output_path.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>

#include "rayscout/core/input_error.h"

namespace rayscout {

void check_output_path(const std::filesystem::path& path, const std::string& label) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(label + ": is a directory");
  const std::filesystem::path parent = path.parent_path();
  if (!parent.empty() && !std::filesystem::is_directory(parent, ec))
    throw InputError(label + ": folder " + parent.string() + " does not exist");
  // Open it for writing as the writer will, without truncating a file that exists; a file the
  // probe creates is removed again. Only regular files and new paths are probed: opening a
  // FIFO for writing would wait for a reader (devices are left to the writer too).
  const bool exists = std::filesystem::exists(path, ec);
  if (exists && !std::filesystem::is_regular_file(path, ec)) return;
  const int fd = ::open(path.c_str(), O_WRONLY | O_APPEND | (exists ? 0 : O_CREAT | O_EXCL), 0666);
  if (fd < 0) throw InputError(label + ": cannot open for writing: " + std::strerror(errno));
  ::close(fd);
  if (!exists) std::filesystem::remove(path, ec);
}

void write_file(const std::filesystem::path& path, std::string_view bytes, const std::string& label) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw InputError(label + ": cannot open " + path.string() + " for writing: " + std::strerror(errno));
  out.write(bytes.data(), std::streamsize(bytes.size()));
  out.close();
  if (!out) throw InputError(label + ": cannot write " + path.string() + " (" + std::to_string(bytes.size()) + " bytes)");
}

}  // namespace rayscout
