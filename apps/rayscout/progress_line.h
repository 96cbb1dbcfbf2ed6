// One line of progress on stderr, redrawn in place, for commands whose work takes long.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <string>

#include <fmt/core.h>

namespace rayscout::cli {

/// Draws only on a terminal (stdout and pipes stay clean). The line is cleared when the work
/// ends, by end() or when it goes out of scope, so that what is printed next (the summary, an
/// error message unwinding past it) starts the line, and a script running many commands
/// leaves no progress lines behind.
class ProgressLine {
 public:
  /// Replaces the line with `text` (\33[K clears the rest of the previous one).
  void draw(const std::string& text) {
    if (!on_) return;
    fmt::print(stderr, "\r{}\33[K", text);
    std::fflush(stderr);
    open_ = true;
  }
  // Clearing instead of ending with a newline also leaves no empty line when someone else
  // ended the line already (the many-light integrator does, before its summary).
  void end() {
    if (open_) fmt::print(stderr, "\r\33[K");
    std::fflush(stderr);
    open_ = false;
  }
  /// Whether lines are drawn (stderr is a terminal).
  bool on() const { return on_; }
  ~ProgressLine() { end(); }

 private:
  bool on_ = isatty(STDERR_FILENO) != 0;
  bool open_ = false;
};

}  // namespace rayscout::cli
