// Output files: checked for writing before the work (check_output_path), written whole (write_file).
#include "rayscout/core/output_path.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <climits>
#include <csignal>
#include <cstring>
#include <mutex>

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

namespace {

// Writes all of bytes to fd; false (errno set) on the first error.
bool write_all(int fd, std::string_view bytes) {
  for (size_t done = 0; done < bytes.size();) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += size_t(n);
  }
  return true;
}

// The temporaries being written, for the handler of SIGINT, SIGTERM and SIGHUP to remove: a
// fixed table, as a signal handler may neither allocate nor lock. A slot is free, being
// filled (by a writer; the handler skips it), holding a temporary's path, or taken by the
// handler (which then ends the process, so the slot is never freed).
enum SlotState : int { kFree, kFilling, kRegistered, kRemoving };
struct TemporarySlot {
  std::atomic<int> state{kFree};
  char path[PATH_MAX];
};
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler needs lock-free atomics");
// More writes at once than slots (or a path too long to open) go unregistered: their
// temporaries are left behind on a signal, as they all were before.
TemporarySlot temporary_slots[32];

// Reserves a slot for `path`; -1 when none is free or the path does not fit.
int register_temporary(const std::filesystem::path& path) {
  const std::string& name = path.native();
  if (name.size() >= PATH_MAX) return -1;
  for (int i = 0; i < int(std::size(temporary_slots)); ++i) {
    TemporarySlot& slot = temporary_slots[i];
    int expected = kFree;
    if (!slot.state.compare_exchange_strong(expected, kFilling, std::memory_order_acquire)) continue;
    std::memcpy(slot.path, name.c_str(), name.size() + 1);
    slot.state.store(kRegistered, std::memory_order_release);
    return i;
  }
  return -1;
}

// Frees the slot once its temporary is renamed or removed (unless a handler took it).
void unregister_temporary(int slot) {
  if (slot < 0) return;
  int expected = kRegistered;
  temporary_slots[slot].state.compare_exchange_strong(expected, kFree, std::memory_order_release);
}

// Removes the registered temporaries, then ends the process by the same signal, with its
// default action, so that its exit status says so (a shell sees "killed by SIGINT"). Only
// async-signal-safe calls.
void remove_temporaries_and_reraise(int sig) {
  const int saved_errno = errno;
  for (TemporarySlot& slot : temporary_slots) {
    int expected = kRegistered;
    if (slot.state.compare_exchange_strong(expected, kRemoving, std::memory_order_acquire)) ::unlink(slot.path);
  }
  struct sigaction default_action {};
  default_action.sa_handler = SIG_DFL;
  sigemptyset(&default_action.sa_mask);
  ::sigaction(sig, &default_action, nullptr);
  // Pending until this handler returns and unblocks it; then it ends the process.
  ::raise(sig);
  errno = saved_errno;
}


// Creates a file of its own beside `target` (".NAME.PID-N.tmp"), with the permissions a new
// file gets, or those of the file it will replace, registered for removal on a signal (`slot`,
// -1 when it could not be); -1 (errno set) when it cannot.
int create_temporary(const std::filesystem::path& target, std::filesystem::path& temporary, int& slot) {
  static std::atomic<unsigned> counter{0};
  struct stat old {};
  const bool replaces = ::stat(target.c_str(), &old) == 0;
  for (int attempt = 0; attempt < 100; ++attempt) {
    // ".NAME.PID-N.tmp", appended piece by piece: GCC 12 warns falsely (-Wrestrict) of "." + s.
    std::string name(1, '.');
    name += target.filename().string();
    name += '.';
    name += std::to_string(::getpid());
    name += '-';
    name += std::to_string(counter++);
    name += ".tmp";
    temporary = target.parent_path() / name;
    // Registered before it exists, so that no signal comes between creating and registering
    // it (a signal before the open removes nothing, or at worst a stale file of the same name).
    slot = register_temporary(temporary);
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) {
      const int error = errno;
      unregister_temporary(slot);
      slot = -1;
      if (error == EEXIST) continue;
      errno = error;
      return -1;
    }
    if (replaces) ::fchmod(fd, old.st_mode & 07777);
    return fd;
  }
  errno = EEXIST;
  return -1;
}

/// Writes bytes to fd and closes it; false, with errno's value in error, when either fails (a
/// full disk is often reported only by the last flush, at close).
bool write_and_close(int fd, std::string_view bytes, int& error) {
  bool ok = write_all(fd, bytes);
  error = errno;
  if (::close(fd) != 0 && ok) {
    ok = false;
    error = errno;
  }
  return ok;
}

}  // namespace

void write_file(const std::filesystem::path& path, std::string_view bytes, const std::string& label) {
  auto failure = [&](const std::string& what, int error) {
    return InputError(label + ": " + what + (error ? std::string(": ") + std::strerror(error) : ""));
  };
  const std::string cannot_write = "cannot write " + path.string() + " (" + std::to_string(bytes.size()) + " bytes)";
  // The file a link leads to is replaced, the link kept.
  const std::filesystem::path target = link_target(path, label);
  std::error_code ec;
  const bool exists = std::filesystem::exists(target, ec);
  const bool regular = exists && std::filesystem::is_regular_file(target, ec);
  // Written beside the target and renamed over it once whole: a failed or interrupted write
  // (a full disk, Ctrl-C) never leaves a partial file under the name, nor spoils the old one.
  std::filesystem::path temporary;
  int slot = -1;
  const int fd = exists && !regular ? -1 : create_temporary(target, temporary, slot);
  if (fd < 0) {
    const int open_error = errno;
    // A device or FIFO (/dev/stdout, /dev/full) cannot be renamed over, and a writable file in
    // a folder that is not cannot get a file beside it: written in place, as a last resort.
    if (!exists || (regular && open_error != EACCES))
      throw failure("cannot open " + path.string() + " for writing", open_error);
    const int in_place = ::open(target.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
    if (in_place < 0) throw failure("cannot open " + path.string() + " for writing", errno);
    if (int error = 0; !write_and_close(in_place, bytes, error)) {
      // A prefix of the bytes, the old contents already truncated: removed, so that no partial
      // file passes for a whole one.
      if (regular) std::filesystem::remove(target, ec);
      throw failure(cannot_write, error);
    }
    return;
  }
  // Unregistered only once renamed or removed: a signal in between unlinks a name that is gone.
  if (int error = 0; !write_and_close(fd, bytes, error)) {
    ::unlink(temporary.c_str());
    unregister_temporary(slot);
    throw failure(cannot_write, error);
  }
  if (::rename(temporary.c_str(), target.c_str()) != 0) {
    const int error = errno;
    ::unlink(temporary.c_str());
    unregister_temporary(slot);
    throw failure(cannot_write, error);
  }
  unregister_temporary(slot);
}

// Only where the signal still has its default action: one the program ignores (SIGHUP under
// nohup, SIGINT in a background job) or handles itself is left so.
void remove_temporaries_on_signals() {
  static std::once_flag once;
  std::call_once(once, [] {
    struct sigaction action {};
    action.sa_handler = remove_temporaries_and_reraise;
    sigemptyset(&action.sa_mask);
    // One handler at a time: a second signal waits until the first has ended the process.
    for (const int sig : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&action.sa_mask, sig);
    action.sa_flags = SA_RESTART;
    for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
      struct sigaction old {};
      if (::sigaction(sig, nullptr, &old) == 0 && !(old.sa_flags & SA_SIGINFO) && old.sa_handler == SIG_DFL)
        ::sigaction(sig, &action, nullptr);
    }
  });
}

}  // namespace rayscout
