// Wavefront OBJ reader with exact file:line diagnostics (its MTL libraries: mtl_reader.cpp).
//
// Hand-written rather than tinyobjloader (2.0.0rc10, the Debian package): it reports an
// out-of-range index with the line number of the end of the file, not of the face; it
// parses "v 1 abc 2" and "v nan 0 0" silently (unparsable numbers become 0); and it
// builds per-vertex attribute arrays we do not need. Here every error names its line.
#include <cerrno>
#include <cstring>
#include <fstream>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "polygon.h"
#include "rayscout/scene/mesh.h"
#include "text_parse.h"

namespace rayscout {
namespace {

using detail::expect_line_end;
using detail::fail_at;
using detail::next_token;
using detail::read_vec3;
using detail::refuse_binary_line;

// Resolves a 1-based or negative OBJ index. Positive indices may point forward (checked
// at the end of the file against the final count); negative ones are relative to now.
long long resolve_index(long long idx, size_t count, const std::filesystem::path& file, size_t line,
                        std::string_view what) {
  if (idx > 0) return idx - 1;
  if (idx == 0) fail_at(file, line, std::string(what) + " index 0 is invalid (OBJ indices start at 1)");
  if (idx < -static_cast<long long>(count))  // not -idx > count: -idx overflows for the smallest index
    fail_at(file, line, (what == "vertex" ? std::string("face") : std::string(what)) + " index " + std::to_string(idx) +
                            " out of range (" + detail::count_of(count, what) + " so far)");
  return static_cast<long long>(count) + idx;
}

// Largest positive index of one kind and the first line that used it.
struct MaxRef {
  long long index = -1;
  size_t line = 0;
  void note(long long i, size_t l) {
    if (i > index) { index = i; line = l; }
  }
};

// One OBJ file being read: the mesh so far, the materials in order of first use, and the
// largest positive indices, which may point forward and are checked at the end of the file.
class ObjReader {
 public:
  explicit ObjReader(const std::filesystem::path& path) : path_(path) {}

  Mesh read() {
    const std::string data = detail::read_file(path_);
    mesh_.positions.reserve(data.size() / 64);
    mesh_.faces.reserve(data.size() / 64);
    bool any_statement = false;  // one parsed: for the message about binary data
    detail::for_each_statement(data, [&](size_t line, std::string_view key, const char* q, const char* end) {
      if (key == "v") vertex(line, q, end);
      else if (key == "vt") attribute(line, q, end, "texcoord", 1, 3, "1 to 3 numbers (u [v [w]])", num_vt_);
      else if (key == "vn") attribute(line, q, end, "normal", 3, 3, "3 numbers (x y z)", num_vn_);
      else if (key == "f") face(line, q, end);
      else if (key == "usemtl") use_material(line, q, end);
      else if (key == "mtllib") material_libraries(line, q, end);
      else  // g, o, s, l, p, vp, ...: not needed for triangles
        return refuse_binary_line({key.data(), size_t(end - key.data())}, any_statement, path_, line, "OBJ");
      any_statement = true;
    });
    check_forward_indices();
    if (mesh_.faces.empty()) throw InputError(detail::display_name(path_) + ": no faces (empty mesh)");
    if (const size_t kept = detail::ear_clip_concave(mesh_, polygons_))
      mesh_.warnings.push_back(detail::concave_fans_kept(detail::display_name(path_), kept));
    resolve_materials();
    return std::move(mesh_);
  }

 private:
  // v x y z, then optionally w, or a colour r g b (a common extension), or r g b a. Anything
  // else is refused: two statements run together (a file with classic Mac CR line ends read as
  // one line) used to give a single vertex and no error.
  void vertex(size_t line, const char* q, const char* end) {
    mesh_.positions.push_back(read_vec3(q, end, path_, line, "vertex", "coordinate"));
    int extra = 0;
    double value;
    for (const char* r = q; detail::parse_double(next_token(r, end), value); q = r) ++extra;
    expect_line_end(q, end, path_, line, "vertex", "the 3 coordinates");
    if (extra > 4)
      fail_at(path_, line, "vertex: " + std::to_string(3 + extra) + " numbers (expected x y z, then w, r g b or r g b a)");
  }

  // vt u [v [w]] or vn x y z: counted, so that face indices can be checked, but not stored
  // (rayscout uses geometric normals). Checked for form only, min to max numbers (`form` says
  // which): exporters write NaN normals for degenerate faces, which rayscout never reads.
  void attribute(size_t line, const char* q, const char* end, std::string_view what, int min, int max,
                 std::string_view form, size_t& count) {
    int n = 0;
    for (std::string_view tok = next_token(q, end); !tok.empty(); tok = next_token(q, end), ++n)
      if (double value; !detail::parse_double(tok, value))
        fail_at(path_, line, std::string(what) + ": " + detail::quoted(tok) + " is not a number");
    if (n < min || n > max)
      fail_at(path_, line, std::string(what) + ": expected " + std::string(form) + ", found " + std::to_string(n));
    ++count;
  }

  // f v1 v2 v3 ...: a polygon, fanned into triangles from its first vertex (ear-clipped at the
  // end of the file if the fan leaves it).
  void face(size_t line, const char* q, const char* end) {
    poly_.clear();
    for (std::string_view tok = next_token(q, end); !tok.empty(); tok = next_token(q, end))
      poly_.push_back(face_vertex(line, tok));
    if (poly_.size() < 3)
      fail_at(path_, line, detail::face_too_small(poly_.size()));
    if (current_ == UINT32_MAX) current_ = material_index("default", line);
    detail::add_polygon(poly_, current_, mesh_, polygons_);
  }

  // One face vertex, v, v/vt, v//vn or v/vt/vn: returns the position index; the texcoord and
  // normal indices are only checked (rayscout uses geometric normals).
  uint32_t face_vertex(size_t line, std::string_view tok) {
    std::string_view parts[3];
    int np = 0;
    for (size_t start = 0;;) {
      const size_t slash = tok.find('/', start);
      if (np == 3) fail_at(path_, line, "face vertex '" + std::string(tok) + "' has more than 3 parts");
      parts[np++] = tok.substr(start, slash - start);
      if (slash == std::string_view::npos) break;
      start = slash + 1;
    }
    long long idx;
    if (!detail::parse_int(parts[0], idx)) fail_at(path_, line, "face vertex '" + std::string(tok) + "' is not an index");
    const long long v = resolve_index(idx, mesh_.positions.size(), path_, line, "vertex");
    max_v_.note(v, line);
    if (v > UINT32_MAX - 1) fail_at(path_, line, "face index " + std::to_string(idx) + " too large");
    if (np > 1 && !(parts[1].empty() && np == 3))  // v//vn has no texcoord
      attribute_index(line, tok, parts[1], "texcoord", num_vt_, max_vt_);
    if (np > 2) attribute_index(line, tok, parts[2], "normal", num_vn_, max_vn_);
    return uint32_t(v);
  }

  // The texcoord or normal index `part` of face vertex `tok`, checked against the `count` so far
  // and noted in `max` for the check of forward indices.
  void attribute_index(size_t line, std::string_view tok, std::string_view part, std::string_view what, size_t count,
                       MaxRef& max) {
    if (part.empty()) fail_at(path_, line, "face vertex '" + std::string(tok) + "' has an empty index");
    long long idx;
    if (!detail::parse_int(part, idx)) fail_at(path_, line, "face vertex '" + std::string(tok) + "' is not an index");
    max.note(resolve_index(idx, count, path_, line, what), line);
  }

  void use_material(size_t line, const char* q, const char* end) {
    const std::string_view name = detail::rest_trimmed(q, end);
    if (name.empty()) fail_at(path_, line, "usemtl without a material name");
    current_ = material_index(std::string(name), line);
  }

  // mtllib: reads each library it names once. A library named again (by any spelling of its path)
  // is not read again, nor said again to be missing: each reread warned once per material that it
  // was "defined again" (3000 mtllib lines of a 1000-material MTL: 3M warnings).
  void material_libraries(size_t line, const char* q, const char* end) {
    for (const std::string& name : library_names(line, q, end)) {
      const std::filesystem::path mtl = path_.parent_path() / name;
      if (libraries_seen_.insert(detail::same_file_key(mtl)).second) read_library(line, name, mtl);
    }
  }

  // The file names of an mtllib line [q, end): one name that may contain spaces when such a file
  // exists, else the space-separated names.
  std::vector<std::string> library_names(size_t line, const char* q, const char* end) const {
    const std::string_view names = detail::rest_trimmed(q, end);
    if (names.empty()) fail_at(path_, line, "mtllib without a file name");
    // The OS reads a path up to its first NUL: "mtllib red.mtl<NUL>junk" read red.mtl.
    if (names.find('\0') != std::string_view::npos)
      fail_at(path_, line, "mtllib '" + std::string(names) + "': a NUL byte in the file name, which no file name can contain");
    std::error_code ec;
    if (std::filesystem::exists(path_.parent_path() / names, ec)) return {std::string(names)};
    std::vector<std::string> files;
    for (std::string_view t = next_token(q, end); !t.empty(); t = next_token(q, end)) files.emplace_back(t);
    return files;
  }

  // Reads the library `name` (at path mtl) named on `line`. A missing one is a warning (its
  // materials get defaults); one that is not a readable file is an error at that line.
  void read_library(size_t line, const std::string& name, const std::filesystem::path& mtl) {
    std::error_code ec;
    if (!std::filesystem::exists(mtl, ec)) {
      library_missing_ = true;
      mesh_.warnings.push_back(detail::at_line(path_, line, "material library '" + name + "' not found; its materials get defaults"));
      return;
    }
    if (const std::string why = detail::not_a_file(mtl); !why.empty())
      fail_at(path_, line, "material library '" + name + "' " + why);
    if (std::ifstream probe(mtl); !probe)
      fail_at(path_, line, "material library '" + name + "' cannot be read: " + std::strerror(errno));
    read_mtl(mtl, library_, &mesh_.warnings);
  }

  void check_forward_indices() const {
    auto check = [&](const MaxRef& m, size_t count, const char* label, const char* what) {
      if (m.index >= static_cast<long long>(count))
        fail_at(path_, m.line, std::string(label) + " index " + std::to_string(m.index + 1) + " out of range (" +
                                   detail::count_of(count, what) + ")");
    };
    check(max_v_, mesh_.positions.size(), "face", "vertex");
    check(max_vt_, num_vt_, "texcoord", "texcoord");
    check(max_vn_, num_vn_, "normal", "normal");
  }

  // The mesh's materials, in order of first use: from the libraries, else a grey diffuse. An
  // undefined name is warned about at its first use, unless a library is missing, which explains
  // them all in one warning.
  void resolve_materials() {
    std::unordered_map<std::string_view, const Material*> library;  // names are unique (read_mtl)
    for (const Material& m : library_) library.emplace(m.name, &m);
    std::vector<size_t> undefined;
    for (size_t i = 0; i < used_names_.size(); ++i) {
      const std::string& name = used_names_[i];
      if (auto it = library.find(name); it != library.end()) {
        mesh_.materials.push_back(*it->second);
        continue;
      }
      Material m;
      m.name = name;
      if (name != "default") undefined.push_back(i);
      mesh_.materials.push_back(m);
    }
    if (undefined.empty()) return;
    if (library_missing_) {
      mesh_.warnings.push_back(missing_library_warning(undefined));
      return;
    }
    for (size_t i : undefined)
      mesh_.warnings.push_back(detail::at_line(path_, used_lines_[i], "material '" + used_names_[i] +
                                                                          "' is not defined in any material library; using a grey diffuse"));
  }

  // The one warning for the materials `undefined` (indices into used_names_) when a library is
  // missing, naming the first five (Crytek Sponza without its MTL: 24 warnings otherwise).
  std::string missing_library_warning(const std::vector<size_t>& undefined) const {
    constexpr size_t kListed = 5;
    std::string names;
    for (size_t k = 0; k < undefined.size() && k < kListed; ++k) names += (k ? ", " : "") + detail::quoted(used_names_[undefined[k]]);
    if (undefined.size() > kListed) names += ", ...";
    const size_t n = undefined.size();
    return detail::at_line(path_, used_lines_[undefined[0]],
                           std::to_string(n) + (n == 1 ? " material (" : " materials (") + names +
                               ") not defined, as a material library is missing; " + (n == 1 ? "it gets" : "they get") +
                               " a grey diffuse");
  }

  uint32_t material_index(const std::string& name, size_t line) {
    auto [it, added] = used_index_.emplace(name, uint32_t(used_names_.size()));
    if (added) {
      used_names_.push_back(name);
      used_lines_.push_back(line);
    }
    return it->second;
  }

  const std::filesystem::path& path_;
  Mesh mesh_;
  std::vector<Material> library_;                        // from mtllib statements
  std::unordered_set<std::string> libraries_seen_;       // canonical paths of the mtllib files
  std::vector<std::string> used_names_;                  // usemtl names in order of first use
  std::vector<size_t> used_lines_;                       // the line of each name's first use
  std::unordered_map<std::string, uint32_t> used_index_;
  bool library_missing_ = false;                         // an mtllib file was not found
  uint32_t current_ = UINT32_MAX;                        // faces before any usemtl: "default"
  size_t num_vt_ = 0, num_vn_ = 0;
  MaxRef max_v_, max_vt_, max_vn_;
  std::vector<uint32_t> poly_;
  std::vector<detail::FannedPolygon> polygons_;  // of 4 or more vertices, for ear_clip_concave
};

}  // namespace

Mesh read_obj(const std::filesystem::path& path) { return ObjReader(path).read(); }

}  // namespace rayscout
