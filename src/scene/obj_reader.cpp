// Wavefront OBJ + MTL reader with exact file:line diagnostics.
//
// Hand-written rather than tinyobjloader (2.0.0rc10, the Debian package): it reports an
// out-of-range index with the line number of the end of the file, not of the face; it
// parses "v 1 abc 2" and "v nan 0 0" silently (unparsable numbers become 0); and it
// builds per-vertex attribute arrays we do not need. Here every error names its line.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <unordered_map>
#include <vector>

#include "rayscout/scene/mesh.h"
#include "text_parse.h"

namespace rayscout {
namespace {

using detail::fail_at;
using detail::next_token;

// Reads three numbers (the rest of the line may hold more, e.g. w or vertex colours).
Vec3 read_vec3(const char*& p, const char* end, const std::filesystem::path& file, size_t line,
               std::string_view what, bool allow_one = false) {
  float c[3];
  int n = 0;
  for (; n < 3; ++n) {
    std::string_view tok = next_token(p, end);
    if (tok.empty()) break;
    if (!detail::parse_float(tok, c[n])) {
      double d;
      if (detail::parse_double(tok, d))
        fail_at(file, line, std::string(what) + ": coordinate " + std::string(tok) + " is out of float range");
      fail_at(file, line, std::string(what) + ": '" + std::string(tok) + "' is not a number");
    }
    if (!std::isfinite(c[n]))
      fail_at(file, line, std::string(what) + ": coordinate " + std::string(tok) + " is not finite");
  }
  if (n == 1 && allow_one) return Vec3(c[0]);
  if (n < 3)
    fail_at(file, line, std::string(what) + ": expected 3 numbers, found " + std::to_string(n));
  return {c[0], c[1], c[2]};
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
  return where + ": material '" + m.name + "': " + (m.type == Material::Type::Mirror ? "Ks" : "Kd + Ks") +
         " reaches " + max + " in a channel (> 1 reflects more light than arrives); Kd and Ks scaled by 1/" + max;
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
  detail::for_each_statement(data, [&](size_t line, std::string_view key, const char* q, const char* line_end) {
    if (key == "newmtl") {
      std::string_view name = detail::rest_trimmed(q, line_end);
      if (name.empty()) fail_at(path, line, "newmtl without a name");
      defs.push_back({});
      defs.back().name = std::string(name);
      defs.back().line = line;
      return;
    }
    const bool known = key == "Kd" || key == "Ks" || key == "Ke" || key == "Ns" || key == "illum";
    if (!known) return;  // Ka, Ni, d, Tr, Tf, map_*, bump...: not used by rayscout
    if (defs.empty()) fail_at(path, line, std::string(key) + " before any newmtl");
    Pending& d = defs.back();
    // Colours: one number (grey) or three, each >= 0, as in JSON scenes (a negative
    // reflectance or emission would make negative radiance).
    auto colour = [&](std::string_view what) {
      const Vec3 c = read_vec3(q, line_end, path, line, what, true);
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
    } else {
      std::string_view tok = next_token(q, line_end);
      long long v;
      if (!detail::parse_int(tok, v)) fail_at(path, line, "illum: expected an integer, found '" + std::string(tok) + "'");
      d.illum = int(v);
    }
  });
  for (auto& d : defs) {
    Material m = material_from_mtl(d.name, d.kd, d.ks, d.ns, d.illum, d.ke);
    const std::string warning =
        conserve_energy_with_warning(m, detail::display_name(path) + ":" + std::to_string(d.line));
    if (!warning.empty() && warnings) warnings->push_back(warning);
    auto same = std::find_if(out.begin(), out.end(), [&](const Material& o) { return o.name == m.name; });
    if (same != out.end()) *same = std::move(m);
    else out.push_back(std::move(m));
  }
}

Mesh read_obj(const std::filesystem::path& path) {
  const std::string data = detail::read_file(path);
  Mesh mesh;
  std::vector<Material> library;                       // from mtllib statements
  std::vector<std::string> used_names;                 // usemtl names in order of first use
  std::unordered_map<std::string, uint32_t> used_index;
  uint32_t current = UINT32_MAX;                       // faces before any usemtl: "default"
  auto material_index = [&](const std::string& name) {
    auto [it, added] = used_index.emplace(name, uint32_t(used_names.size()));
    if (added) used_names.push_back(name);
    return it->second;
  };

  size_t num_vt = 0, num_vn = 0;
  MaxRef max_v, max_vt, max_vn;
  std::vector<uint32_t> poly;
  mesh.positions.reserve(data.size() / 64);
  mesh.faces.reserve(data.size() / 64);

  detail::for_each_statement(data, [&](size_t line, std::string_view key, const char* q, const char* line_end) {
    if (key == "v") {
      mesh.positions.push_back(read_vec3(q, line_end, path, line, "vertex"));
    } else if (key == "vt") {
      ++num_vt;
    } else if (key == "vn") {
      ++num_vn;
    } else if (key == "f") {
      poly.clear();
      for (std::string_view tok = next_token(q, line_end); !tok.empty(); tok = next_token(q, line_end)) {
        // v, v/vt, v//vn or v/vt/vn
        std::string_view parts[3];
        int np = 0;
        for (size_t i = 0, start = 0;; ++i) {
          if (i == tok.size() || tok[i] == '/') {
            if (np == 3) fail_at(path, line, "face vertex '" + std::string(tok) + "' has more than 3 parts");
            parts[np++] = tok.substr(start, i - start);
            start = i + 1;
            if (i == tok.size()) break;
          }
        }
        long long idx;
        if (!detail::parse_int(parts[0], idx))
          fail_at(path, line, "face vertex '" + std::string(tok) + "' is not an index");
        long long v = resolve_index(idx, mesh.positions.size(), path, line, "vertex");
        max_v.note(v, line);
        if (v > UINT32_MAX - 1) fail_at(path, line, "face index " + std::to_string(idx) + " too large");
        poly.push_back(uint32_t(v));
        const std::string_view kinds[2] = {"texcoord", "normal"};
        size_t counts[2] = {num_vt, num_vn};
        MaxRef* maxes[2] = {&max_vt, &max_vn};
        for (int k = 1; k < np; ++k) {
          if (parts[k].empty()) {
            if (k == 1 && np == 3) continue;  // v//vn
            fail_at(path, line, "face vertex '" + std::string(tok) + "' has an empty index");
          }
          if (!detail::parse_int(parts[k], idx))
            fail_at(path, line, "face vertex '" + std::string(tok) + "' is not an index");
          maxes[k - 1]->note(resolve_index(idx, counts[k - 1], path, line, kinds[k - 1]), line);
        }
      }
      if (poly.size() < 3)
        fail_at(path, line, "face with " + std::to_string(poly.size()) + " vertices (at least 3 needed)");
      if (current == UINT32_MAX) current = material_index("default");
      for (size_t k = 1; k + 1 < poly.size(); ++k) {
        mesh.faces.push_back({poly[0], poly[k], poly[k + 1]});
        mesh.face_materials.push_back(current);
      }
    } else if (key == "usemtl") {
      std::string_view name = detail::rest_trimmed(q, line_end);
      if (name.empty()) fail_at(path, line, "usemtl without a material name");
      current = material_index(std::string(name));
    } else if (key == "mtllib") {
      std::string_view names = detail::rest_trimmed(q, line_end);
      if (names.empty()) fail_at(path, line, "mtllib without a file name");
      // One name that may contain spaces, else several space-separated names.
      std::vector<std::string> files{std::string(names)};
      std::error_code ec;
      if (!std::filesystem::exists(path.parent_path() / files[0], ec)) {
        files.clear();
        for (std::string_view t = next_token(q, line_end); !t.empty(); t = next_token(q, line_end))
          files.emplace_back(t);
      }
      for (const auto& f : files) {
        std::filesystem::path mtl = path.parent_path() / f;
        if (!std::filesystem::exists(mtl, ec)) {
          mesh.warnings.push_back(detail::display_name(path) + ":" + std::to_string(line) +
                                  ": material library '" + f + "' not found; its materials get defaults");
          continue;
        }
        if (std::filesystem::is_directory(mtl, ec))
          fail_at(path, line, "material library '" + f + "' is a directory, not a file");
        read_mtl(mtl, library, &mesh.warnings);
      }
    }
    // g, o, s, l, p, vp, ...: not needed for triangles.
  });

  auto check_max = [&](const MaxRef& m, size_t count, const char* label, const char* what) {
    if (m.index >= static_cast<long long>(count))
      fail_at(path, m.line, std::string(label) + " index " + std::to_string(m.index + 1) + " out of range (" +
                                std::to_string(count) + " " + (count == 1 ? std::string(what) : plural(what)) + ")");
  };
  check_max(max_v, mesh.positions.size(), "face", "vertex");
  check_max(max_vt, num_vt, "texcoord", "texcoord");
  check_max(max_vn, num_vn, "normal", "normal");
  if (mesh.faces.empty()) throw InputError(detail::display_name(path) + ": no faces (empty mesh)");

  for (const auto& name : used_names) {
    auto it = std::find_if(library.begin(), library.end(), [&](const Material& m) { return m.name == name; });
    if (it != library.end()) {
      mesh.materials.push_back(*it);
    } else {
      Material m;
      m.name = name;
      if (name != "default")
        mesh.warnings.push_back(detail::display_name(path) + ": material '" + name +
                                "' is not defined in any material library; using a grey diffuse");
      mesh.materials.push_back(m);
    }
  }
  return mesh;
}

}  // namespace rayscout
