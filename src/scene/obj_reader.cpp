// Wavefront OBJ + MTL reader with exact file:line diagnostics.
//
// Hand-written rather than tinyobjloader (2.0.0rc10, the Debian package): it reports an
// out-of-range index with the line number of the end of the file, not of the face; it
// parses "v 1 abc 2" and "v nan 0 0" silently (unparsable numbers become 0); and it
// builds per-vertex attribute arrays we do not need. Here every error names its line.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "rayscout/scene/mesh.h"
#include "text_parse.h"

namespace rayscout {
namespace {

using detail::expect_line_end;
using detail::fail_at;
using detail::next_token;

// Reads three numbers (the rest of the line may hold more, e.g. w or vertex colours); an
// error names `what` and the number as an `element` ("vertex: coordinate 1e39 ...").
Vec3 read_vec3(const char*& p, const char* end, const std::filesystem::path& file, size_t line,
               std::string_view what, std::string_view element, bool allow_one = false) {
  float c[3];
  int n = 0;
  for (; n < 3; ++n) {
    std::string_view tok = next_token(p, end);
    if (tok.empty()) break;
    if (!detail::parse_float(tok, c[n])) {
      double d;
      if (detail::parse_double(tok, d))
        fail_at(file, line, std::string(what) + ": " + std::string(element) + " " + std::string(tok) + " is out of float range");
      fail_at(file, line, std::string(what) + ": '" + std::string(tok) + "' is not a number");
    }
    if (!std::isfinite(c[n]))
      fail_at(file, line, std::string(what) + ": " + std::string(element) + " " + std::string(tok) + " is not finite");
  }
  if (n == 1 && allow_one) return Vec3(c[0]);
  if (n < 3)
    fail_at(file, line, std::string(what) + ": expected 3 numbers, found " + std::to_string(n));
  return {c[0], c[1], c[2]};
}

// MTL statements rayscout reads past on purpose (ambient, transparency, refraction, bump and
// displacement, the PBR extension), besides every texture "map_*": an unknown key is warned about
// instead, as it is most likely a misspelt one that rayscout reads ("kd": the material stays grey).
constexpr std::string_view kIgnoredMtlStatements[] = {
    "Ka", "Tf", "Ni", "d", "Tr",                               // ambient, transparency, refraction
    "bump", "Km", "disp", "decal", "refl", "sharpness",        // textures named without map_
    "Pr", "Pm", "Ps", "Pc", "Pcr", "aniso", "anisor", "norm"};  // the PBR extension

bool ignored_mtl_statement(std::string_view key) {
  return key.starts_with("map_") ||
         std::find(std::begin(kIgnoredMtlStatements), std::end(kIgnoredMtlStatements), key) !=
             std::end(kIgnoredMtlStatements);
}

// The MTL key rayscout reads that `key` spells in other case ("kd": "Kd"), else empty.
std::string_view read_key_but_for_case(std::string_view key) {
  const auto same = [](char a, char b) { return std::tolower((unsigned char)a) == std::tolower((unsigned char)b); };
  for (std::string_view k : {"Kd", "Ks", "Ke", "Ns", "illum"})
    if (k.size() == key.size() && std::equal(k.begin(), k.end(), key.begin(), same)) return k;
  return {};
}

// Random or binary data read as OBJ or MTL text is a few lines of unknown statements, all ignored
// ("no faces (empty mesh)" for 4 KB of random bytes). A line the reader would ignore that holds a
// byte no text has (NUL, ESC, ...) is refused instead. `text` is the line from its key on.
void refuse_binary_line(std::string_view text, bool after_statements, const std::filesystem::path& file,
                        size_t line, std::string_view format) {
  if (!detail::has_binary_byte(text)) return;
  if (!after_statements) fail_at(file, line, "not an " + std::string(format) + " text file (binary data)");
  fail_at(file, line, "binary data where an " + std::string(format) + " statement belongs (a damaged file?)");
}

std::string plural(std::string_view what) { return what == "vertex" ? "vertices" : std::string(what) + "s"; }

// Resolves a 1-based or negative OBJ index. Positive indices may point forward (checked
// at the end of the file against the final count); negative ones are relative to now.
long long resolve_index(long long idx, size_t count, const std::filesystem::path& file, size_t line,
                        std::string_view what) {
  if (idx > 0) return idx - 1;
  if (idx == 0) fail_at(file, line, std::string(what) + " index 0 is invalid (OBJ indices start at 1)");
  if (idx < -static_cast<long long>(count))  // not -idx > count: -idx overflows for the smallest index
    fail_at(file, line, (what == "vertex" ? std::string("face") : std::string(what)) + " index " + std::to_string(idx) +
                            " out of range (" + std::to_string(count) + " " + plural(what) + " so far)");
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

}  // namespace

Material material_from_mtl(std::string name, const Vec3& kd, const Vec3& ks, float ns, int illum,
                           const Vec3& ke) {
  Material m;
  m.name = std::move(name);
  m.diffuse = kd;
  m.specular = ks;
  m.exponent = ns;
  m.emission = ke;
  const bool has_specular = ks.x > 0 || ks.y > 0 || ks.z > 0;
  const bool mirror_illum = illum == 3 || illum == 5 || illum == 7;
  if (!has_specular) m.type = Material::Type::Diffuse;
  else if (mirror_illum || ns >= 1000.0f) m.type = Material::Type::Mirror;
  else m.type = Material::Type::Glossy;
  return m;
}

float conserve_energy(Material& m) {
  const Vec3 reflectance = m.type == Material::Type::Mirror ? m.specular : m.diffuse + m.specular;
  const float total = max_component(reflectance);
  if (total > 1.0f) {
    m.diffuse = m.diffuse * (1.0f / total);
    m.specular = m.specular * (1.0f / total);
  }
  return total;
}

std::string conserve_energy_with_warning(Material& m, const std::string& where) {
  const float total = conserve_energy(m);
  if (!(total > 1.0f)) return {};
  const std::string max = detail::format_number(total);
  return detail::printable(where + ": material '" + m.name + "': " + (m.type == Material::Type::Mirror ? "Ks" : "Kd + Ks") +
                           " reaches " + max + " in a channel (> 1 reflects more light than arrives); Kd and Ks scaled by 1/" +
                           max);
}

void read_mtl(const std::filesystem::path& path, std::vector<Material>& out, std::vector<std::string>* warnings) {
  const std::string data = detail::read_file(path);
  struct Pending {
    std::string name;
    Vec3 kd{0.8f}, ks{0.0f}, ke{0.0f};
    float ns = 0;
    int illum = 2;
    size_t line = 0;
  };
  std::vector<Pending> defs;
  std::unordered_set<std::string> unknown_keys;  // warned about once each
  bool any_statement = false;                    // a known one: for the message about binary data
  detail::for_each_statement(data, [&](size_t line, std::string_view key, const char* q, const char* line_end) {
    const bool known = key == "Kd" || key == "Ks" || key == "Ke" || key == "Ns" || key == "illum";
    if (!known && key != "newmtl" && !ignored_mtl_statement(key)) {
      refuse_binary_line({key.data(), size_t(line_end - key.data())}, any_statement, path, line, "MTL");
      if (!unknown_keys.emplace(key).second || !warnings) return;
      const std::string_view meant = read_key_but_for_case(key);
      warnings->push_back(detail::at_line(
          path, line,
          "unknown MTL statement '" + std::string(key) + "' ignored" +
              (meant.empty() ? "" : "; keys are case-sensitive: did you mean '" + std::string(meant) + "'?")));
      return;
    }
    any_statement = true;
    if (key == "newmtl") {
      std::string_view name = detail::rest_trimmed(q, line_end);
      if (name.empty()) fail_at(path, line, "newmtl without a name");
      defs.push_back({});
      defs.back().name = std::string(name);
      defs.back().line = line;
      return;
    }
    if (!known) return;  // kIgnoredMtlStatements
    if (defs.empty()) fail_at(path, line, std::string(key) + " before any newmtl");
    Pending& d = defs.back();
    // Colours: one number (grey) or three, each >= 0, as in JSON scenes (a negative
    // reflectance or emission would make negative radiance).
    auto colour = [&](std::string_view what) {
      const Vec3 c = read_vec3(q, line_end, path, line, what, "component", true);
      expect_line_end(q, line_end, path, line, what, "the colour");
      if (c.x < 0 || c.y < 0 || c.z < 0) fail_at(path, line, std::string(what) + ": colour components must be >= 0");
      return c;
    };
    if (key == "Kd") d.kd = colour("Kd");
    else if (key == "Ks") d.ks = colour("Ks");
    else if (key == "Ke") d.ke = colour("Ke");
    else if (key == "Ns") {
      std::string_view tok = next_token(q, line_end);
      if (!detail::parse_float(tok, d.ns) || !std::isfinite(d.ns) || d.ns < 0)
        fail_at(path, line, "Ns: expected a non-negative number, found '" + std::string(tok) + "'");
      expect_line_end(q, line_end, path, line, "Ns", "the exponent");
    } else {
      std::string_view tok = next_token(q, line_end);
      long long v;
      if (!detail::parse_int(tok, v)) fail_at(path, line, "illum: expected an integer, found '" + std::string(tok) + "'");
      if (v < 0 || v > 10) fail_at(path, line, "illum " + std::string(tok) + ": the MTL illumination models are 0 to 10");
      expect_line_end(q, line_end, path, line, "illum", "the model number");
      d.illum = int(v);
    }
  });
  // By name, not by a search of `out` per definition: that was quadratic (an MTL of 100000
  // materials took 80 s).
  std::unordered_map<std::string, size_t> index;
  for (size_t i = 0; i < out.size(); ++i) index.emplace(out[i].name, i);
  for (auto& d : defs) {
    Material m = material_from_mtl(d.name, d.kd, d.ks, d.ns, d.illum, d.ke);
    const std::string warning = conserve_energy_with_warning(m, detail::display_name(path) + ":" + std::to_string(d.line));
    if (!warning.empty() && warnings) warnings->push_back(warning);
    if (auto [it, added] = index.emplace(m.name, out.size()); !added) {
      if (warnings)
        warnings->push_back(detail::at_line(path, d.line, "material '" + m.name + "' defined again; this later definition is used"));
      out[it->second] = std::move(m);
    } else {
      out.push_back(std::move(m));
    }
  }
}

namespace {

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
      else if (key == "vt") ++num_vt_;
      else if (key == "vn") ++num_vn_;
      else if (key == "f") face(line, q, end);
      else if (key == "usemtl") use_material(line, q, end);
      else if (key == "mtllib") material_libraries(line, q, end);
      else  // g, o, s, l, p, vp, ...: not needed for triangles
        return refuse_binary_line({key.data(), size_t(end - key.data())}, any_statement, path_, line, "OBJ");
      any_statement = true;
    });
    check_forward_indices();
    if (mesh_.faces.empty()) throw InputError(detail::display_name(path_) + ": no faces (empty mesh)");
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

  // f v1 v2 v3 ...: a polygon, fanned into triangles from its first vertex.
  void face(size_t line, const char* q, const char* end) {
    poly_.clear();
    for (std::string_view tok = next_token(q, end); !tok.empty(); tok = next_token(q, end))
      poly_.push_back(face_vertex(line, tok));
    if (poly_.size() < 3)
      fail_at(path_, line, detail::face_too_small(poly_.size()));
    if (current_ == UINT32_MAX) current_ = material_index("default", line);
    for (size_t k = 1; k + 1 < poly_.size(); ++k) {
      mesh_.faces.push_back({poly_[0], poly_[k], poly_[k + 1]});
      mesh_.face_materials.push_back(current_);
    }
  }

  // One face vertex, v, v/vt, v//vn or v/vt/vn: returns the position index; the texcoord and
  // normal indices are only checked (rayscout uses geometric normals).
  uint32_t face_vertex(size_t line, std::string_view tok) {
    std::string_view parts[3];
    int np = 0;
    for (size_t i = 0, start = 0;; ++i) {
      if (i == tok.size() || tok[i] == '/') {
        if (np == 3) fail_at(path_, line, "face vertex '" + std::string(tok) + "' has more than 3 parts");
        parts[np++] = tok.substr(start, i - start);
        start = i + 1;
        if (i == tok.size()) break;
      }
    }
    long long idx;
    if (!detail::parse_int(parts[0], idx)) fail_at(path_, line, "face vertex '" + std::string(tok) + "' is not an index");
    const long long v = resolve_index(idx, mesh_.positions.size(), path_, line, "vertex");
    max_v_.note(v, line);
    if (v > UINT32_MAX - 1) fail_at(path_, line, "face index " + std::to_string(idx) + " too large");
    const std::string_view kinds[2] = {"texcoord", "normal"};
    const size_t counts[2] = {num_vt_, num_vn_};
    MaxRef* maxes[2] = {&max_vt_, &max_vn_};
    for (int k = 1; k < np; ++k) {
      if (parts[k].empty()) {
        if (k == 1 && np == 3) continue;  // v//vn
        fail_at(path_, line, "face vertex '" + std::string(tok) + "' has an empty index");
      }
      if (!detail::parse_int(parts[k], idx)) fail_at(path_, line, "face vertex '" + std::string(tok) + "' is not an index");
      maxes[k - 1]->note(resolve_index(idx, counts[k - 1], path_, line, kinds[k - 1]), line);
    }
    return uint32_t(v);
  }

  void use_material(size_t line, const char* q, const char* end) {
    const std::string_view name = detail::rest_trimmed(q, end);
    if (name.empty()) fail_at(path_, line, "usemtl without a material name");
    current_ = material_index(std::string(name), line);
  }

  // mtllib: one name that may contain spaces, else several space-separated names. A missing
  // library is a warning: its materials get defaults. A library named again (by any spelling of
  // its path) is not read again, nor said again to be missing: each reread warned once per
  // material that it was "defined again" (3000 mtllib lines of a 1000-material MTL: 3M warnings).
  void material_libraries(size_t line, const char* q, const char* end) {
    const std::string_view names = detail::rest_trimmed(q, end);
    if (names.empty()) fail_at(path_, line, "mtllib without a file name");
    // The OS reads a path up to its first NUL: "mtllib red.mtl<NUL>junk" read red.mtl.
    if (names.find('\0') != std::string_view::npos)
      fail_at(path_, line, "mtllib '" + std::string(names) + "': a NUL byte in the file name, which no file name can contain");
    std::vector<std::string> files{std::string(names)};
    std::error_code ec;
    if (!std::filesystem::exists(path_.parent_path() / files[0], ec)) {
      files.clear();
      for (std::string_view t = next_token(q, end); !t.empty(); t = next_token(q, end)) files.emplace_back(t);
    }
    for (const auto& f : files) {
      const std::filesystem::path mtl = path_.parent_path() / f;
      // absolute() first: weakly_canonical keeps "gone.mtl" relative but makes "./gone.mtl"
      // absolute when the OBJ was named without a folder, so the two keys differed.
      std::string key = std::filesystem::weakly_canonical(std::filesystem::absolute(mtl, ec), ec).string();
      if (ec) key = mtl.lexically_normal().string();
      if (!libraries_seen_.insert(std::move(key)).second) continue;
      if (!std::filesystem::exists(mtl, ec)) {
        mesh_.warnings.push_back(detail::at_line(path_, line, "material library '" + f + "' not found; its materials get defaults"));
        continue;
      }
      // As read_file refuses them, but said at the mtllib line that names them.
      using std::filesystem::file_type;
      const file_type type = std::filesystem::status(mtl, ec).type();
      if (type == file_type::directory) fail_at(path_, line, "material library '" + f + "' is a directory, not a file");
      if (type == file_type::character || type == file_type::block)
        fail_at(path_, line, "material library '" + f + "' is a device, not a file");
      if (std::ifstream probe(mtl); !probe)
        fail_at(path_, line, "material library '" + f + "' cannot be read: " + std::strerror(errno));
      read_mtl(mtl, library_, &mesh_.warnings);
    }
  }

  void check_forward_indices() const {
    auto check = [&](const MaxRef& m, size_t count, const char* label, const char* what) {
      if (m.index >= static_cast<long long>(count))
        fail_at(path_, m.line, std::string(label) + " index " + std::to_string(m.index + 1) + " out of range (" +
                                   std::to_string(count) + " " + (count == 1 ? std::string(what) : plural(what)) + ")");
    };
    check(max_v_, mesh_.positions.size(), "face", "vertex");
    check(max_vt_, num_vt_, "texcoord", "texcoord");
    check(max_vn_, num_vn_, "normal", "normal");
  }

  // The mesh's materials, in order of first use: from the libraries, else a grey diffuse.
  void resolve_materials() {
    std::unordered_map<std::string_view, const Material*> library;  // names are unique (read_mtl)
    for (const Material& m : library_) library.emplace(m.name, &m);
    for (size_t i = 0; i < used_names_.size(); ++i) {
      const std::string& name = used_names_[i];
      if (auto it = library.find(name); it != library.end()) {
        mesh_.materials.push_back(*it->second);
        continue;
      }
      Material m;
      m.name = name;
      if (name != "default")
        mesh_.warnings.push_back(detail::at_line(
            path_, used_lines_[i], "material '" + name + "' is not defined in any material library; using a grey diffuse"));
      mesh_.materials.push_back(m);
    }
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
  uint32_t current_ = UINT32_MAX;                        // faces before any usemtl: "default"
  size_t num_vt_ = 0, num_vn_ = 0;
  MaxRef max_v_, max_vt_, max_vn_;
  std::vector<uint32_t> poly_;
};

}  // namespace

Mesh read_obj(const std::filesystem::path& path) { return ObjReader(path).read(); }

}  // namespace rayscout
