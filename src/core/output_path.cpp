// Output files: checked for writing before the work (check_output_path), written whole (write_file).
#include "rayscout/core/output_path.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>

#include "rayscout/core/input_error.h"

namespace rayscout {

namespace {

// Where a file or a symbolic link chain ends: the target a writer opening `path` creates or
// replaces (a dangling link is written through, not replaced).
std::filesystem::path link_target(const std::filesystem::path& path, const std::string& label) {
  std::filesystem::path p = path;
  std::error_code ec;
  for (int hops = 0; std::filesystem::is_symlink(std::filesystem::symlink_status(p, ec)); ++hops) {
    if (hops == 40) throw InputError(label + ": too many levels of symbolic links");
    const std::filesystem::path to = std::filesystem::read_symlink(p, ec);
    if (ec) throw InputError(label + ": cannot read the symbolic link " + p.string() + ": " + ec.message());
    p = to.is_absolute() ? to : p.parent_path() / to;
  }
  return p;
}

bool names_a_file(const NamedFile& f) { return !f.path.empty() && f.path != "-"; }

}  // namespace

void check_output_path(const std::filesystem::path& path, const std::string& label) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(label + ": is a directory");
  // A symbolic link: probe where it leads (a dangling link's target is created by the writer;
  // probing the link itself failed with "File exists").
  if (const std::filesystem::path target = link_target(path, label); target != path) {
    check_output_path(target, label);
    return;
  }
  const std::filesystem::path parent = path.parent_path();
  if (!parent.empty() && !std::filesystem::is_directory(parent, ec))
    throw InputError(label + (std::filesystem::exists(parent, ec) ? ": " + parent.string() + " is a file, not a folder"
                                                                    : ": folder " + parent.string() + " does not exist"));
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

void check_distinct_files(std::span<const NamedFile> outputs, std::span<const NamedFile> inputs) {
  // One file: the same inode when both exist, else the same absolute path with links resolved.
  auto same = [](const std::filesystem::path& a, const std::filesystem::path& b) {
    std::error_code ec;
    if (std::filesystem::exists(a, ec) && std::filesystem::exists(b, ec)) return std::filesystem::equivalent(a, b, ec);
    const std::filesystem::path ca = std::filesystem::weakly_canonical(std::filesystem::absolute(a, ec), ec);
    if (ec) return false;
    const std::filesystem::path cb = std::filesystem::weakly_canonical(std::filesystem::absolute(b, ec), ec);
    return !ec && ca == cb;
  };
  std::error_code ec;
  for (size_t i = 0; i < outputs.size(); ++i) {
    const NamedFile& out = outputs[i];
    if (!names_a_file(out)) continue;
    for (const NamedFile& in : inputs)  // an input that is no file (a built-in scene) is never overwritten
      if (names_a_file(in) && std::filesystem::exists(in.path, ec) && same(out.path, in.path))
        throw InputError(out.label + ": is also " + in.label + ", which would be overwritten");
    for (size_t j = 0; j < i; ++j)
      if (names_a_file(outputs[j]) && same(out.path, outputs[j].path))
        throw InputError(out.label + ": is also the output " + outputs[j].label);
  }
}

void write_file(const std::filesystem::path& path, std::string_view bytes, const std::string& label) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw InputError(label + ": cannot open " + path.string() + " for writing: " + std::strerror(errno));
  errno = 0;
  out.write(bytes.data(), std::streamsize(bytes.size()));
  out.close();
  if (!out) {
    const int error = errno;
    // The file holds a prefix of the bytes (a full disk, a file size limit): removed, so that
    // no truncated image or ray file is left to pass for a whole one. Its old contents were
    // already truncated by the open. Devices (/dev/full) and a link itself are left alone.
    std::error_code ec;
    try {
      if (const std::filesystem::path target = link_target(path, label); std::filesystem::is_regular_file(target, ec))
        std::filesystem::remove(target, ec);
    } catch (const InputError&) {  // a link that cannot be followed: nothing was written through it
    }
    throw InputError(label + ": cannot write " + path.string() + " (" + std::to_string(bytes.size()) + " bytes)" +
                     (error ? std::string(": ") + std::strerror(error) : ""));
  }
}

}  // namespace rayscout
