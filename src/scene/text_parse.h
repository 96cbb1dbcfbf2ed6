// Private helpers of the scene readers: whole-file reads, tokens, numbers, located errors.
#pragma once

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>
#include <type_traits>

#include "rayscout/core/input_error.h"
#include "rayscout/core/vec3.h"

namespace rayscout::detail {

/// The whole file; throws InputError "path: cannot open ..." when it cannot be read, and refuses
/// what not_a_file names.
std::string read_file(const std::filesystem::path& path);

/// "is a directory, not a file" or "is a device, not a file" (a device has no end to read to:
/// /dev/zero was read until memory ran out); empty for a file, a pipe, or a path that does not exist.
std::string not_a_file(const std::filesystem::path& path);

/// Start of the text after a UTF-8 byte order mark, if any.
inline const char* skip_bom(const std::string& data) {
  return data.size() >= 3 && data.compare(0, 3, "\xEF\xBB\xBF") == 0 ? data.data() + 3 : data.data();
}

/// "file:line: message" with control bytes escaped: the form of every located error and warning.
std::string at_line(const std::filesystem::path& file, size_t line, const std::string& message);

/// Throws InputError(at_line(file, line, message)).
[[noreturn]] void fail_at(const std::filesystem::path& file, size_t line, const std::string& message);

/// The plural of a noun of the messages: "vertices", else the noun + "s" ("faces", "normals").
inline std::string plural(std::string_view noun) { return noun == "vertex" ? "vertices" : std::string(noun) + "s"; }

/// "1 vertex", "3 vertices": a count of a noun of the messages.
inline std::string count_of(size_t n, std::string_view noun) {
  return std::to_string(n) + " " + (n == 1 ? std::string(noun) : plural(noun));
}

/// "face with n vertices (at least 3 needed)": the OBJ and PLY readers' message.
inline std::string face_too_small(size_t n) { return "face with " + count_of(n, "vertex") + " (at least 3 needed)"; }

/// Deepest nesting of arrays and objects accepted in JSON text (scene files, glTF).
inline constexpr int kMaxJsonDepth = 256;

/// Throws InputError naming line and column where `text` nests arrays and objects deeper
/// than kMaxJsonDepth. Checked on the text, before any parser sees it: nlohmann's copies
/// recurse once per level (a scene file nested 20000 deep overflowed the stack), and so
/// does assimp's glTF reader (a glTF with 200000 nested arrays in its "extras" crashed it).
void check_json_nesting(std::string_view text, const std::string& file);

/// "invalid JSON: what", what = nlohmann's message without its "[json.exception.parse_error.101] "
/// id (the message names line and column itself).
inline std::string invalid_json(std::string what) {
  if (auto p = what.find("] "); p != std::string::npos) what = what.substr(p + 2);
  return "invalid JSON: " + what;
}

inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

/// True when `text` holds a control byte that no text has (NUL, ESC, DEL, ...; tab, CR, LF, FF and
/// VT are white space). Nearly every line of random or binary data holds one.
inline bool has_binary_byte(std::string_view text) {
  for (const char c : text)
    if ((static_cast<unsigned char>(c) < 0x20 && !is_space(c) && c != '\n') || c == 0x7f) return true;
  return false;
}

/// Next whitespace-separated token of [p, end), advancing p; empty at the end.
inline std::string_view next_token(const char*& p, const char* end) {
  while (p < end && is_space(*p)) ++p;
  const char* b = p;
  while (p < end && !is_space(*p)) ++p;
  return {b, size_t(p - b)};
}

/// Throws "file:line: what: unexpected 'tok' after <after>" when a token is left in [p, end) after a
/// statement's values ("Kd 1 0 0 abc", "v 1 0 0 v 0 1 0", "element face 1 2"): ignored, it would
/// hide a typo or two statements run together.
inline void expect_line_end(const char* p, const char* end, const std::filesystem::path& file, size_t line,
                            std::string_view what, std::string_view after) {
  if (const std::string_view tok = next_token(p, end); !tok.empty())
    fail_at(file, line, std::string(what) + ": unexpected '" + std::string(tok) + "' after " + std::string(after));
}

/// Reads three numbers of a statement (OBJ, MTL) from [p, end), advancing p; the line may hold
/// more. With allow_one, a single number v gives (v, v, v) (an MTL grey). Errors name `what` and
/// call a number an `element` ("vertex: coordinate 1e39 is out of float range").
Vec3 read_vec3(const char*& p, const char* end, const std::filesystem::path& file, size_t line, std::string_view what,
               std::string_view element, bool allow_one = false);

/// Random or binary data read as OBJ or MTL text is a few lines of unknown statements, all ignored
/// ("no faces (empty mesh)" for 4 KB of random bytes). So a line the reader would ignore that holds
/// a byte no text has (NUL, ESC, ...) is refused: "not an <format> text file (binary data)", or
/// after_statements, a damaged file. `text` is the line from its key on.
void refuse_binary_line(std::string_view text, bool after_statements, const std::filesystem::path& file, size_t line,
                        std::string_view format);

/// Rest of the line with surrounding whitespace removed.
inline std::string_view rest_trimmed(const char* p, const char* end) {
  while (p < end && is_space(*p)) ++p;
  while (end > p && is_space(end[-1])) --end;
  return {p, size_t(end - p)};
}

/// Parses a whole token as a number of type T (a leading '+' allowed; for floats "nan"/"inf"
/// parse so the caller can name them). False when the token is not entirely a number or overflows.
/// A float too small for T (1e-50 for float) gives the nearest T, a denormal or a signed 0, as a
/// JSON number does (read as double, then rounded to float); from_chars refuses it.
template <typename T>
inline bool parse_number(std::string_view tok, T& out) {
  const char* b = tok.data();
  const char* e = b + tok.size();
  if (b < e && *b == '+') ++b;
  if (b == e) return false;
  auto [ptr, ec] = std::from_chars(b, e, out);
  if constexpr (std::is_floating_point_v<T>) {
    // strtod (the token is a whole number, so it reads it the same) rounds an underflow to the
    // nearest double and an overflow to HUGE_VAL; then the cast to T decides as in JSON.
    if (ec == std::errc::result_out_of_range && ptr == e) {
      out = static_cast<T>(std::strtod(std::string(b, e).c_str(), nullptr));
      return std::isfinite(out);
    }
  }
  return ec == std::errc() && ptr == e;
}
inline bool parse_float(std::string_view tok, float& out) { return parse_number(tok, out); }
inline bool parse_double(std::string_view tok, double& out) { return parse_number(tok, out); }
inline bool parse_int(std::string_view tok, long long& out) { return parse_number(tok, out); }

/// The line at p up to the line end eol (excluded), or to end; p moves past the line end.
inline std::string_view next_line(const char*& p, const char* end, char eol) {
  const char* nl = static_cast<const char*>(std::memchr(p, eol, size_t(end - p)));
  const std::string_view line(p, size_t((nl ? nl : end) - p));
  p = nl ? nl + 1 : end;
  return line;
}

/// Calls f(line, key, p, end) for every non-empty statement of a line-based text file (OBJ,
/// MTL): line is 1-based, key the first token, [p, end) the rest with any '#' comment cut off.
/// Lines end in LF or CR LF, or in CR alone in a file without any LF (classic Mac OS).
template <typename F>
void for_each_statement(const std::string& data, F&& f) {
  const char* p = skip_bom(data);
  const char* const end = data.data() + data.size();
  const bool cr_only = !std::memchr(p, '\n', size_t(end - p)) && std::memchr(p, '\r', size_t(end - p));
  const char line_end_char = cr_only ? '\r' : '\n';
  size_t line = 0;
  while (p < end) {
    const std::string_view text = next_line(p, end, line_end_char);
    const char* q = text.data();
    const char* line_end = q + text.size();
    ++line;
    if (const void* hash = std::memchr(q, '#', size_t(line_end - q))) line_end = static_cast<const char*>(hash);
    const std::string_view key = next_token(q, line_end);
    if (!key.empty()) f(line, key, q, line_end);
  }
}

/// The same string for every spelling of a path ("a.mtl", "./a.mtl", "sub/../a.mtl", a link to
/// it), whether or not the file exists: a key for reading each file once.
std::string same_file_key(const std::filesystem::path& path);

/// The file name as shown in messages, control bytes escaped (a NUL cut messages short).
inline std::string display_name(const std::filesystem::path& p) { return printable(p.string()); }

/// 'text' for messages. Appended piece by piece: g++ 12 warns (-Wrestrict, a false positive) on
/// "'" + std::string(text) where it is inlined.
inline std::string quoted(std::string_view text) {
  std::string s;
  s.reserve(text.size() + 2);
  s += '\'';
  s += text;
  s += '\'';
  return s;
}

/// A number for messages: %g, 6 significant digits ("1.563", "2", "1e+20").
inline std::string format_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace rayscout::detail
