// One line of progress on stderr, redrawn in place, for commands whose work takes long.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <string>

#include <fmt/core.h>

namespace rayscout::cli {

/// Draws only on a terminal (stdout and pipes stay clean). The line is ended before anything
/// else is printed: by end(), or when it goes out of scope, so that an error message unwinding
/// past it starts on a line of its own.
class ProgressLine {
 public:
  /// Replaces the line with `text` (\33[K clears the rest of the previous one).
  void draw(const std::string& text) {
    if (!on_) return;
    fmt::print(stderr, "\r{}\33[K", text);
    std::fflush(stderr);
    open_ = true;
  }
  void end() {
    if (open_) fmt::print(stderr, "\n");
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
