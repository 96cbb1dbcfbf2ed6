// Checking an output path before the work that ends by writing it, and writing it whole.
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <string_view>

namespace rayscout {

/// Throws InputError, prefixed with `label` (e.g. "--stats out.json"), unless `path` can be
/// written as a file: it is not a directory, its folder exists, and it opens for writing (an
/// existing file is left as it is, a new one is removed again). Commands call it before long
/// work, so that a mistyped or unwritable output path never costs a finished render.
void check_output_path(const std::filesystem::path& path, const std::string& label);

/// A file a command reads or writes, as its command line names it (label "--out a.png").
struct NamedFile {
  std::filesystem::path path;
  std::string label;
};

/// Throws InputError "OUTPUT-LABEL: is also INPUT-LABEL" when an output names an existing input
/// file (writing it would destroy what the command reads), or "... is also the output ..." when
/// two outputs name one file (the last written would silently replace the other). Symbolic
/// links and relative paths are followed. Empty paths and "-" (stdout) are skipped.
void check_distinct_files(std::span<const NamedFile> outputs, std::span<const NamedFile> inputs);

/// Writes bytes to path, replacing it whole: to a temporary file beside it (".NAME.PID-N.tmp"),
/// renamed over it once written and closed (a full disk is often reported only by the last
/// flush), so that a failed or interrupted write never leaves a partial file under the name nor
/// spoils the file it replaces. A symbolic link is written through (its target replaced, the
/// link kept) and a replaced file keeps its permissions; a device (/dev/stdout) is written in
/// place. Throws InputError "label: cannot write path (...)" on any failure.
/// Safe to call from several threads at once.
void write_file(const std::filesystem::path& path, std::string_view bytes, const std::string& label);

/// Makes Ctrl-C (SIGINT), SIGTERM and SIGHUP remove the temporaries write_file is writing
/// (up to 32 at once), then end the process by the same signal (exit status "killed by
/// SIGINT"). Installs a handler for each of those signals that still has its default action:
/// one the program ignores or handles itself is left alone. For programs (the CLI calls it
/// first thing); a library never installs signal handlers on its own. Idempotent.
void remove_temporaries_on_signals();

}  // namespace rayscout
