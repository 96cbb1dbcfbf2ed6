// InputError: the one exception type for bad user input (files, fields, options).
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

namespace rayscout {

/// Bad user input that names what was wrong (an option, a file and line, a field). Commands
/// report it with exit code 2; anything else escaping is a bug.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Text for a message that quotes input (a name, a field, a line, a binary file's magic):
/// control bytes (NUL, ESC, DEL, the C1 controls) and bytes that are not well-formed UTF-8 as
/// \xNN, so that the message prints whole (what() is a C string: a NUL ended it) and plainly
/// on a terminal (a material named "<ESC>[2J" cleared it; a lone 0x9B is CSI to some). Other
/// UTF-8 characters stay as they are, so names in other scripts remain readable.
std::string printable(std::string_view text);

}  // namespace rayscout
