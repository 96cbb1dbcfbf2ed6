// printable: input quoted in messages, made safe to print.
#include "rayscout/core/input_error.h"

#include <cstdio>

namespace rayscout {
namespace {

/// Length of the well-formed UTF-8 sequence of a printable character at text[i] (Unicode
/// table 3-7: no overlong forms, surrogates or code points above U+10FFFF), or 0.
size_t printable_utf8_length(std::string_view text, size_t i) {
  const auto byte = [&](size_t k) { return i + k < text.size() ? static_cast<unsigned char>(text[i + k]) : 0u; };
  const unsigned lead = byte(0);
  // The second byte's range depends on the lead; later ones are 0x80..0xBF.
  size_t n = 0;
  unsigned lo = 0x80, hi = 0xBF;
  if (lead >= 0xC2 && lead <= 0xDF) n = 2;
  else if (lead >= 0xE0 && lead <= 0xEF) n = 3, lo = lead == 0xE0 ? 0xA0 : 0x80, hi = lead == 0xED ? 0x9F : 0xBF;
  else if (lead >= 0xF0 && lead <= 0xF4) n = 4, lo = lead == 0xF0 ? 0x90 : 0x80, hi = lead == 0xF4 ? 0x8F : 0xBF;
  else return 0;
  if (byte(1) < lo || byte(1) > hi) return 0;
  for (size_t k = 2; k < n; ++k)
    if (byte(k) < 0x80 || byte(k) > 0xBF) return 0;
  // U+0080..U+009F (C2 80..C2 9F) are the C1 controls: CSI (U+009B) starts an escape sequence.
  if (lead == 0xC2 && byte(1) <= 0x9F) return 0;
  return n;
}

}  // namespace

std::string printable(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size();) {
    const auto u = static_cast<unsigned char>(text[i]);
    if (u >= 0x20 && u < 0x7f) {
      out += text[i++];
      continue;
    }
    if (const size_t n = u >= 0x80 ? printable_utf8_length(text, i) : 0) {
      out += text.substr(i, n);  // names in other scripts stay readable
      i += n;
      continue;
    }
    char buf[8];
    std::snprintf(buf, sizeof buf, "\\x%02x", unsigned(u));
    out += buf;
    ++i;
  }
  return out;
}

}  // namespace rayscout
