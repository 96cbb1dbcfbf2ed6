// PLY reader (ascii, binary little and big endian) with file:line or element/byte diagnostics.
//
// Hand-written for the same reason as the OBJ reader: assimp's PLY importer reports errors
// without lines or byte offsets and accepts out-of-range indices and NaN coordinates.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <string>
#include <unordered_map>
#include <vector>

#include "polygon.h"
#include "rayscout/scene/mesh.h"
#include "text_parse.h"

namespace rayscout {
namespace {

using detail::fail_at;
using detail::next_token;

enum class Scalar { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool scalar_from_name(std::string_view n, Scalar& s) {
  if (n == "char" || n == "int8") s = Scalar::Int8;
  else if (n == "uchar" || n == "uint8") s = Scalar::UInt8;
  else if (n == "short" || n == "int16") s = Scalar::Int16;
  else if (n == "ushort" || n == "uint16") s = Scalar::UInt16;
  else if (n == "int" || n == "int32") s = Scalar::Int32;
  else if (n == "uint" || n == "uint32") s = Scalar::UInt32;
  else if (n == "float" || n == "float32") s = Scalar::Float32;
  else if (n == "double" || n == "float64") s = Scalar::Float64;
  else return false;
  return true;
}

size_t scalar_size(Scalar s) {
  switch (s) {
    case Scalar::Int8: case Scalar::UInt8: return 1;
    case Scalar::Int16: case Scalar::UInt16: return 2;
    case Scalar::Int32: case Scalar::UInt32: case Scalar::Float32: return 4;
    case Scalar::Float64: return 8;
  }
  return 0;
}

// The name and range of an integer type, for ascii values beyond it ("300 for uchar").
struct IntRange {
  const char* name;
  long long lo, hi;
};

IntRange int_range(Scalar s) {
  switch (s) {
    case Scalar::Int8: return {"char", INT8_MIN, INT8_MAX};
    case Scalar::UInt8: return {"uchar", 0, UINT8_MAX};
    case Scalar::Int16: return {"short", INT16_MIN, INT16_MAX};
    case Scalar::UInt16: return {"ushort", 0, UINT16_MAX};
    case Scalar::Int32: return {"int", INT32_MIN, INT32_MAX};
    default: return {"uint", 0, UINT32_MAX};
  }
}

struct Property {
  std::string name;
  Scalar type = Scalar::Float32;
  bool is_list = false;
  Scalar count_type = Scalar::UInt8;
};

struct Element {
  std::string name;
  size_t count = 0;
  std::vector<Property> props;
  size_t header_line = 0;
};

enum class Format { Ascii, BinaryLittle, BinaryBig };

// Reads one binary scalar as double; false when the data ends first.
bool read_binary(const char*& p, const char* end, Scalar s, bool swap, double& out) {
  size_t n = scalar_size(s);
  if (size_t(end - p) < n) return false;
  unsigned char b[8];
  if (swap) {
    for (size_t i = 0; i < n; ++i) b[i] = static_cast<unsigned char>(p[n - 1 - i]);
  } else {
    std::memcpy(b, p, n);
  }
  p += n;
  switch (s) {
    case Scalar::Int8: { int8_t v; std::memcpy(&v, b, 1); out = v; break; }
    case Scalar::UInt8: out = b[0]; break;
    case Scalar::Int16: { int16_t v; std::memcpy(&v, b, 2); out = v; break; }
    case Scalar::UInt16: { uint16_t v; std::memcpy(&v, b, 2); out = v; break; }
    case Scalar::Int32: { int32_t v; std::memcpy(&v, b, 4); out = v; break; }
    case Scalar::UInt32: { uint32_t v; std::memcpy(&v, b, 4); out = v; break; }
    case Scalar::Float32: { float v; std::memcpy(&v, b, 4); out = v; break; }
    case Scalar::Float64: { double v; std::memcpy(&v, b, 8); out = v; break; }
  }
  return true;
}

// A number as written in the file, shortest form: "1.5", "nan", "1e+30" (a float-typed index).
std::string number_text(double v) {
  char buf[32];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return ec == std::errc() ? std::string(buf, end) : std::to_string(v);
}

struct Header {
  Format format = Format::Ascii;
  std::vector<Element> elements;
  char eol = '\n';  // '\r' for a file with classic Mac line ends ("ply\r" not followed by '\n')
};

// The statement readers get the rest of the line after the keyword in [q, e).

// "format ascii|binary_little_endian|binary_big_endian 1.0".
Format format_statement(const std::filesystem::path& path, size_t line, const char* q, const char* e) {
  Format format = Format::Ascii;
  const std::string_view f = next_token(q, e);
  if (f == "ascii") format = Format::Ascii;
  else if (f == "binary_little_endian") format = Format::BinaryLittle;
  else if (f == "binary_big_endian") format = Format::BinaryBig;
  else fail_at(path, line, "unknown PLY format '" + std::string(f) + "'");
  const std::string_view version = next_token(q, e);
  if (version.empty()) fail_at(path, line, "format line without a version (expected 'format " + std::string(f) + " 1.0')");
  if (double v; !detail::parse_double(version, v) || v != 1.0)
    fail_at(path, line, "unsupported PLY version '" + std::string(version) + "' (1.0 is the only one)");
  detail::expect_line_end(q, e, path, line, "format", "the version");
  return format;
}

// "element <name> <count>"; `earlier` are the elements declared before it.
Element element_statement(const std::filesystem::path& path, size_t line, const char* q, const char* e,
                          const std::vector<Element>& earlier) {
  Element el;
  el.name = std::string(next_token(q, e));
  const std::string_view c = next_token(q, e);
  long long n;
  if (el.name.empty() || !detail::parse_int(c, n) || n < 0) fail_at(path, line, "element: expected 'element <name> <count>'");
  detail::expect_line_end(q, e, path, line, "element", "the count");
  // Each vertex element would need its own x, y, z positions; one is all a mesh has.
  if (el.name == "vertex") {
    for (const auto& other : earlier)
      if (other.name == "vertex")
        fail_at(path, line, "a second vertex element (the first is on line " + std::to_string(other.header_line) + ")");
    if (n > static_cast<long long>(UINT32_MAX))
      fail_at(path, line, "element vertex: " + std::string(c) + " vertices, more than 32-bit face indices can address");
  }
  el.count = size_t(n);
  el.header_line = line;
  return el;
}

// "property <type> <name>" or "property list <count type> <type> <name>".
Property property_statement(const std::filesystem::path& path, size_t line, const char* q, const char* e) {
  Property prop;
  std::string_view t = next_token(q, e);
  if (t == "list") {
    prop.is_list = true;
    const std::string_view ct = next_token(q, e);
    if (!scalar_from_name(ct, prop.count_type)) fail_at(path, line, "unknown PLY type '" + std::string(ct) + "'");
    if (prop.count_type == Scalar::Float32 || prop.count_type == Scalar::Float64)
      fail_at(path, line, "list count type must be an integer type");
    t = next_token(q, e);
  }
  if (!scalar_from_name(t, prop.type)) fail_at(path, line, "unknown PLY type '" + std::string(t) + "'");
  prop.name = std::string(next_token(q, e));
  if (prop.name.empty()) fail_at(path, line, "property without a name");
  detail::expect_line_end(q, e, path, line, "property", "the name");
  return prop;
}

// Reads the header from p (left after end_header); line counts the lines read.
Header read_header(const std::filesystem::path& path, const char*& p, const char* end, size_t& line) {
  Header h;
  if (end - p >= 5 && std::string_view(p, 4) == "ply\r" && p[4] != '\n') h.eol = '\r';
  // Next header line, without its newline.
  auto header_line = [&](std::string_view& out) {
    if (p >= end) return false;
    out = detail::next_line(p, end, h.eol);
    if (!out.empty() && out.back() == '\r') out.remove_suffix(1);
    ++line;
    return true;
  };

  std::string_view hl;
  if (!header_line(hl) || hl != "ply") fail_at(path, 1, "not a PLY file (first line must be 'ply')");
  size_t format_line = 0;  // 0 until the format line
  std::unordered_map<std::string, size_t> property_lines;  // of the current element: a header may hold 10^6
  for (;;) {
    if (!header_line(hl)) fail_at(path, line, "header has no end_header");
    const char* q = hl.data();
    const char* e = q + hl.size();
    const std::string_view key = next_token(q, e);
    if (key.empty() || key == "comment" || key == "obj_info") continue;
    if (key == "end_header") {
      detail::expect_line_end(q, e, path, line, "end_header", "it");
      break;
    }
    if (key == "format") {
      if (format_line)
        fail_at(path, line, "a second format line (the first is on line " + std::to_string(format_line) + ")");
      h.format = format_statement(path, line, q, e);
      format_line = line;
    } else if (key == "element") {
      h.elements.push_back(element_statement(path, line, q, e, h.elements));
      property_lines.clear();
    } else if (key == "property") {
      if (h.elements.empty()) fail_at(path, line, "property before any element");
      Property prop = property_statement(path, line, q, e);
      Element& el = h.elements.back();
      if (const auto [first, fresh] = property_lines.emplace(prop.name, line); !fresh)
        fail_at(path, line, "a second property " + prop.name + " in element " + el.name + " (the first is on line " +
                                std::to_string(first->second) + ")");
      el.props.push_back(std::move(prop));
    } else {
      fail_at(path, line, "unknown header keyword '" + std::string(key) + "'");
    }
  }
  if (!format_line) throw InputError(detail::display_name(path) + ": header has no format line");
  return h;
}

// The vertex element's count and the indices of its x, y, z properties.
struct VertexLayout {
  size_t count = 0;
  int x = -1, y = -1, z = -1;
};

VertexLayout vertex_layout(const std::filesystem::path& path, const std::vector<Element>& elements) {
  VertexLayout v;
  for (const auto& el : elements) {
    if (el.name != "vertex") continue;
    v.count = el.count;
    for (size_t i = 0; i < el.props.size(); ++i) {
      const auto& pr = el.props[i];
      int* slot = pr.name == "x" ? &v.x : pr.name == "y" ? &v.y : pr.name == "z" ? &v.z : nullptr;
      if (slot && !pr.is_list) *slot = int(i);
    }
    if (v.x < 0 || v.y < 0 || v.z < 0) fail_at(path, el.header_line, "vertex element lacks x, y or z properties");
  }
  return v;
}

// The index of a face element's vertex index list.
int face_index_property(const std::filesystem::path& path, const Element& el) {
  for (size_t i = 0; i < el.props.size(); ++i)
    if (el.props[i].is_list && (el.props[i].name == "vertex_indices" || el.props[i].name == "vertex_index"))
      return int(i);
  fail_at(path, el.header_line, "face element lacks a vertex_indices list");
}

// The values of one element instance after another, from the body after the header: an ascii
// instance is one line, a binary one its bytes. Errors name the line (ascii) or the element,
// its index and the byte offset where the instance starts (binary).
class InstanceReader {
 public:
  InstanceReader(const std::filesystem::path& path, const Header& header, const std::string& data, const char* p,
                 size_t line)
      : path_(path), header_(header), data_(data), p_(p), line_(line) {}

  bool binary() const { return header_.format != Format::Ascii; }

  // Starts instance k of element el.
  void begin(const Element& el, size_t k) {
    el_ = &el;
    k_ = k;
    byte_ = size_t(p_ - data_.data());
    if (binary()) return;
    if (p_ >= end()) fail_at(path_, line_ + 1, "unexpected end of file in " + instance());
    const std::string_view text = detail::next_line(p_, end(), header_.eol);
    q_ = text.data();
    e_ = q_ + text.size();
    ++line_;
  }

  // The next value of the instance. Ascii numbers are parsed by their declared type, so float
  // coordinates round once and integer indices stay exact.
  double next(Scalar type, const std::string& property) {
    if (binary()) {
      double x = 0;
      if (!read_binary(p_, end(), type, swap(), x))
        fail("unexpected end of data (" + detail::count_of(el_->count, el_->name) + " declared)");
      return x;
    }
    const std::string_view t = next_token(q_, e_);
    if (t.empty()) fail("too few values for " + instance() + " (property " + property + ")");
    if (type == Scalar::Float32) {
      float f;
      if (!detail::parse_float(t, f)) {
        double d;
        fail(detail::quoted(t) + (detail::parse_double(t, d) ? " is out of float range" : " is not a number"));
      }
      return f;
    }
    if (type == Scalar::Float64) {
      double d;
      if (!detail::parse_double(t, d)) fail(detail::quoted(t) + " is not a number");
      return d;
    }
    long long i;
    if (!detail::parse_int(t, i)) fail(detail::quoted(t) + " is not an integer");
    if (const IntRange r = int_range(type); i < r.lo || i > r.hi)
      fail(detail::quoted(t) + " is out of range for " + r.name + " (" + std::to_string(r.lo) + " to " +
           std::to_string(r.hi) + ")");
    return double(i);
  }

  // Ends the instance: an ascii line must hold no more values than the header declares. The
  // instance is named with the count: a count larger than the data reads the next element's
  // first line as one more of these ("vertex 3 of 10" on the line of the first face).
  void finish() {
    if (binary()) return;
    if (const std::string_view t = next_token(q_, e_); !t.empty())
      fail("more values than the header declares for " + instance() + " ('" + std::string(t) + "')");
  }

  // After the last element. Ascii: only white space may follow. Binary: bytes after it are
  // ignored, as rply does (it stops after the declared elements); writers pad files or append
  // data the header does not describe, and the declared elements were all read whole.
  void finish_file() {
    while (!binary() && p_ < end()) {
      const std::string_view text = detail::next_line(p_, end(), header_.eol);
      const char* q = text.data();
      ++line_;
      if (const std::string_view t = next_token(q, q + text.size()); !t.empty())
        fail_at(path_, line_, "data after the last element ('" + std::string(t) + "')");
    }
  }

  [[noreturn]] void fail(const std::string& message) const {
    if (binary())
      throw InputError(printable(detail::display_name(path_) + ": " + el_->name + " " + std::to_string(k_) +
                                         " (byte " + std::to_string(byte_) + "): " + message));
    fail_at(path_, line_, message);
  }

 private:
  // "vertex 3 of 10": the instance being read (0-based) and its element's count.
  std::string instance() const { return el_->name + " " + std::to_string(k_) + " of " + std::to_string(el_->count); }
  const char* end() const { return data_.data() + data_.size(); }
  bool swap() const { return (header_.format == Format::BinaryBig) != (std::endian::native == std::endian::big); }

  const std::filesystem::path& path_;
  const Header& header_;
  const std::string& data_;
  const char* p_;       // the next byte of the body
  size_t line_;         // ascii: the line just read
  const Element* el_ = nullptr;
  size_t k_ = 0;        // the instance's index in its element
  size_t byte_ = 0;     // where the instance starts
  const char* q_ = nullptr;  // ascii: the rest of the instance's line [q_, e_)
  const char* e_ = nullptr;
};

// Reads the values of the instance `in` has begun: values[i] is property i's (0 for a list); the
// entries of the list face_prop (-1: none), integers checked, go to `indices`.
void read_values(InstanceReader& in, const Element& el, int face_prop, std::vector<double>& values,
                 std::vector<double>& indices) {
  values.clear();
  indices.clear();
  for (size_t i = 0; i < el.props.size(); ++i) {
    const Property& pr = el.props[i];
    if (!pr.is_list) {
      values.push_back(in.next(pr.type, pr.name));
      continue;
    }
    values.push_back(0);
    const double count = in.next(pr.count_type, pr.name);
    if (count < 0) in.fail("negative list length");
    for (size_t j = 0; j < size_t(count); ++j) {
      const double v = in.next(pr.type, pr.name);
      if (int(i) != face_prop) continue;
      if (v != std::floor(v)) in.fail("face index " + number_text(v) + " is not an integer");
      indices.push_back(v);
    }
  }
  in.finish();
}

// The vertex of one vertex instance; a coordinate that is not finite in float is an error.
Vec3 vertex_position(InstanceReader& in, const std::vector<double>& values, const VertexLayout& layout) {
  const Vec3 v(float(values[size_t(layout.x)]), float(values[size_t(layout.y)]), float(values[size_t(layout.z)]));
  if (!is_finite(v)) {
    // A finite double beyond the float range becomes inf here: say which and why.
    for (int a : {layout.x, layout.y, layout.z}) {
      const double d = values[size_t(a)];
      if (!std::isfinite(d)) in.fail("vertex coordinate " + number_text(d) + " is not finite");
      if (!std::isfinite(float(d))) in.fail("vertex coordinate " + detail::format_number(d) + " is out of float range");
    }
  }
  return v;
}

// Appends one face, fan-triangulated (ear-clipped later if the fan leaves it); its indices are
// checked against the declared vertex count before any conversion to an integer.
void add_face(InstanceReader& in, const std::vector<double>& indices, size_t vertex_count, Mesh& mesh,
              std::vector<detail::FannedPolygon>& polygons, std::vector<uint32_t>& poly) {
  if (indices.size() < 3) in.fail(detail::face_too_small(indices.size()));
  poly.clear();
  for (double idx : indices) {
    if (!(idx >= 0 && idx < double(vertex_count)))
      in.fail("face index " + number_text(idx) + " out of range (" + detail::count_of(vertex_count, "vertex") + ")");
    poly.push_back(uint32_t(idx));
  }
  detail::add_polygon(poly, 0, mesh, polygons);
}

}  // namespace

Mesh read_ply(const std::filesystem::path& path) {
  const std::string data = detail::read_file(path);
  const char* p = data.data();
  size_t line = 0;
  const Header header = read_header(path, p, data.data() + data.size(), line);
  const VertexLayout vertices = vertex_layout(path, header.elements);
  InstanceReader in(path, header, data, p, line);

  Mesh mesh;
  mesh.materials.push_back(Material{.name = "default"});
  // A header may declare absurd counts; never reserve more than the data could hold.
  mesh.positions.reserve(std::min(vertices.count, data.size() / 3));
  std::vector<double> values, indices;
  std::vector<detail::FannedPolygon> polygons;  // of 4 or more vertices
  std::vector<uint32_t> poly;                   // one face's indices
  for (const Element& el : header.elements) {
    const bool is_vertex = el.name == "vertex", is_face = el.name == "face";
    const int face_prop = is_face ? face_index_property(path, el) : -1;
    // A binary instance without properties takes no bytes: nothing to read, whatever the count.
    if (in.binary() && el.props.empty()) continue;
    for (size_t k = 0; k < el.count; ++k) {
      in.begin(el, k);
      read_values(in, el, face_prop, values, indices);
      if (is_vertex) mesh.positions.push_back(vertex_position(in, values, vertices));
      if (is_face) add_face(in, indices, vertices.count, mesh, polygons, poly);
    }
  }
  in.finish_file();
  if (mesh.faces.empty()) throw InputError(detail::display_name(path) + ": no faces (empty mesh)");
  if (const size_t kept = detail::ear_clip_concave(mesh, polygons))
    mesh.warnings.push_back(detail::concave_fans_kept(detail::display_name(path), kept));
  return mesh;
}

}  // namespace rayscout
