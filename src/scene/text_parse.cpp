// Whole-file reads, located errors and the statement helpers shared by the scene readers.
#include "text_parse.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

namespace rayscout::detail {

std::string not_a_file(const std::filesystem::path& path) {
  using std::filesystem::file_type;
  std::error_code ec;
  const file_type type = std::filesystem::status(path, ec).type();
  if (type == file_type::directory) return "is a directory, not a file";
  if (type == file_type::character || type == file_type::block) return "is a device, not a file";
  return "";
}

std::string read_file(const std::filesystem::path& path) {
  if (const std::string why = not_a_file(path); !why.empty()) throw InputError(display_name(path) + ": " + why);
  // A pipe is read but cut off at 4 GiB; a regular file of any size is read whole.
  std::error_code ec;
  const bool regular = std::filesystem::is_regular_file(path, ec);
  std::unique_ptr<FILE, int (*)(FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) throw InputError(display_name(path) + ": cannot open: " + std::strerror(errno));
  std::string data;
  if (std::fseek(f.get(), 0, SEEK_END) == 0) {
    long size = std::ftell(f.get());
    if (size > 0) data.reserve(size_t(size));
    std::fseek(f.get(), 0, SEEK_SET);
  }
  constexpr size_t kPipeLimit = size_t(4) << 30;
  char buf[1 << 16];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f.get())) > 0) {
    data.append(buf, n);
    if (!regular && data.size() > kPipeLimit)
      throw InputError(display_name(path) + ": not a regular file, and no end after 4 GiB");
  }
  if (std::ferror(f.get())) throw InputError(display_name(path) + ": read error: " + std::strerror(errno));
  return data;
}

std::string same_file_key(const std::filesystem::path& path) {
  // absolute() first: weakly_canonical keeps "gone.mtl" relative but makes "./gone.mtl" absolute
  // when the path has no folder, so the two keys differed.
  std::error_code ec;
  std::string key = std::filesystem::weakly_canonical(std::filesystem::absolute(path, ec), ec).string();
  return ec ? path.lexically_normal().string() : key;
}

std::string at_line(const std::filesystem::path& file, size_t line, const std::string& message) {
  return printable(display_name(file) + ":" + std::to_string(line) + ": " + message);
}

void fail_at(const std::filesystem::path& file, size_t line, const std::string& message) {
  throw InputError(at_line(file, line, message));
}

Vec3 read_vec3(const char*& p, const char* end, const std::filesystem::path& file, size_t line, std::string_view what,
               std::string_view element, bool allow_one) {
  float c[3];
  int n = 0;
  for (; n < 3; ++n) {
    const std::string_view tok = next_token(p, end);
    if (tok.empty()) break;
    if (!parse_float(tok, c[n])) {
      double d;
      if (parse_double(tok, d))
        fail_at(file, line, std::string(what) + ": " + std::string(element) + " " + std::string(tok) + " is out of float range");
      fail_at(file, line, std::string(what) + ": '" + std::string(tok) + "' is not a number");
    }
    if (!std::isfinite(c[n]))
      fail_at(file, line, std::string(what) + ": " + std::string(element) + " " + std::string(tok) + " is not finite");
  }
  if (n == 1 && allow_one) return Vec3(c[0]);
  if (n < 3) fail_at(file, line, std::string(what) + ": expected 3 numbers, found " + std::to_string(n));
  return {c[0], c[1], c[2]};
}

void refuse_binary_line(std::string_view text, bool after_statements, const std::filesystem::path& file, size_t line,
                        std::string_view format) {
  if (!has_binary_byte(text)) return;
  if (!after_statements) fail_at(file, line, "not an " + std::string(format) + " text file (binary data)");
  fail_at(file, line, "binary data where an " + std::string(format) + " statement belongs (a damaged file?)");
}

void check_json_nesting(std::string_view text, const std::string& file) {
  int depth = 0;
  size_t line = 1, column = 0;
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    ++column;
    if (c == '\n') {
      ++line;
      column = 0;
    } else if (in_string) {
      if (c == '\\') {  // skip the escaped character, e.g. \"
        ++i;
        ++column;
      } else if (c == '"') {
        in_string = false;
      }
    } else if (c == '"') {
      in_string = true;
    } else if ((c == '[' || c == '{') && ++depth > kMaxJsonDepth) {
      throw InputError(file + ": JSON nested deeper than " + std::to_string(kMaxJsonDepth) +
                       " arrays and objects at line " + std::to_string(line) + ", column " + std::to_string(column));
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

}  // namespace rayscout::detail
