// InputError: the one exception type for bad user input (files, fields, options).
#pragma once

#include <stdexcept>

namespace rayscout {

/// Bad user input that names what was wrong (an option, a file and line, a field). Commands
/// report it with exit code 2; anything else escaping is a bug.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace rayscout
