// printable: input quoted in messages, made safe to print.
#include "rayscout/core/input_error.h"

#include <cstdio>

namespace rayscout {

std::string printable(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u != 0x7f) {
      out += c;  // UTF-8 bytes too: names in other scripts stay readable
      continue;
    }
    char buf[8];
    std::snprintf(buf, sizeof buf, "\\x%02x", unsigned(u));
    out += buf;
  }
  return out;
}

}  // namespace rayscout
