// MTL material libraries (of OBJ files) and the MTL mapping to Material that glTF materials share,
// with energy conservation for files rayscout does not control (docs/scene-format.md, Materials).
#include <algorithm>
#include <cctype>
#include <cmath>
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
using detail::read_vec3;
using detail::refuse_binary_line;

// The MTL statements rayscout reads (besides newmtl).
constexpr std::string_view kReadMtlStatements[] = {"Kd", "Ks", "Ke", "Ns", "illum"};

bool is_read_statement(std::string_view key) {
  return std::find(std::begin(kReadMtlStatements), std::end(kReadMtlStatements), key) != std::end(kReadMtlStatements);
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
  for (std::string_view k : kReadMtlStatements)
    if (k.size() == key.size() && std::equal(k.begin(), k.end(), key.begin(), same)) return k;
  return {};
}

// "unknown MTL statement 'kd' ignored", and when it is a key rayscout reads in other case, "did you
// mean 'Kd'?".
std::string unknown_key_warning(const std::filesystem::path& path, size_t line, std::string_view key) {
  const std::string_view meant = read_key_but_for_case(key);
  return detail::at_line(path, line,
                         "unknown MTL statement '" + std::string(key) + "' ignored" +
                             (meant.empty() ? "" : "; keys are case-sensitive: did you mean '" + std::string(meant) + "'?"));
}

// One newmtl definition as written: the MTL values, their defaults where absent.
struct MtlDefinition {
  std::string name;
  Vec3 kd{0.8f}, ks{0.0f}, ke{0.0f};
  float ns = 0;
  int illum = 2;
  size_t line = 0;  // of the newmtl statement
};

// Sets d's value of a statement rayscout reads (Kd, Ks, Ke, Ns or illum); [q, end) is the rest of
// its line, which must hold the value and nothing else.
void read_value(std::string_view key, const char* q, const char* end, const std::filesystem::path& path, size_t line,
                MtlDefinition& d) {
  // Colours: one number (grey) or three, each >= 0, as in JSON scenes (a negative
  // reflectance or emission would make negative radiance).
  auto colour = [&](std::string_view what) {
    const Vec3 c = read_vec3(q, end, path, line, what, "component", true);
    expect_line_end(q, end, path, line, what, "the colour");
    if (c.x < 0 || c.y < 0 || c.z < 0) fail_at(path, line, std::string(what) + ": colour components must be >= 0");
    return c;
  };
  if (key == "Kd") {
    d.kd = colour("Kd");
  } else if (key == "Ks") {
    d.ks = colour("Ks");
  } else if (key == "Ke") {
    d.ke = colour("Ke");
  } else if (key == "Ns") {
    const std::string_view tok = next_token(q, end);
    if (!detail::parse_float(tok, d.ns) || !std::isfinite(d.ns) || d.ns < 0)
      fail_at(path, line, "Ns: expected a non-negative number, found '" + std::string(tok) + "'");
    expect_line_end(q, end, path, line, "Ns", "the exponent");
  } else {
    const std::string_view tok = next_token(q, end);
    long long v;
    if (!detail::parse_int(tok, v)) fail_at(path, line, "illum: expected an integer, found '" + std::string(tok) + "'");
    if (v < 0 || v > 10) fail_at(path, line, "illum " + std::string(tok) + ": the MTL illumination models are 0 to 10");
    expect_line_end(q, end, path, line, "illum", "the model number");
    d.illum = int(v);
  }
}

// The definitions of an MTL file in file order. An unknown key is warned about once per file
// (to `warnings` when given); one on a line of binary data is an error.
std::vector<MtlDefinition> read_definitions(const std::filesystem::path& path, std::vector<std::string>* warnings) {
  const std::string data = detail::read_file(path);
  std::vector<MtlDefinition> defs;
  std::unordered_set<std::string> unknown_keys;  // warned about once each
  bool any_statement = false;                    // a known one: for the message about binary data
  detail::for_each_statement(data, [&](size_t line, std::string_view key, const char* q, const char* end) {
    if (!is_read_statement(key) && key != "newmtl" && !ignored_mtl_statement(key)) {
      refuse_binary_line({key.data(), size_t(end - key.data())}, any_statement, path, line, "MTL");
      if (warnings && unknown_keys.emplace(key).second) warnings->push_back(unknown_key_warning(path, line, key));
      return;
    }
    any_statement = true;
    if (key == "newmtl") {
      const std::string_view name = detail::rest_trimmed(q, end);
      if (name.empty()) fail_at(path, line, "newmtl without a name");
      defs.push_back({.name = std::string(name), .line = line});
    } else if (is_read_statement(key)) {
      if (defs.empty()) fail_at(path, line, std::string(key) + " before any newmtl");
      read_value(key, q, end, path, line, defs.back());
    }
  });
  return defs;
}

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
  return printable(where + ": material '" + m.name + "': " + (m.type == Material::Type::Mirror ? "Ks" : "Kd + Ks") +
                           " reaches " + max + " in a channel (> 1 reflects more light than arrives); Kd and Ks scaled by 1/" +
                           max);
}

void read_mtl(const std::filesystem::path& path, std::vector<Material>& out, std::vector<std::string>* warnings) {
  const std::vector<MtlDefinition> defs = read_definitions(path, warnings);
  // By name, not by a search of `out` per definition: that was quadratic (an MTL of 100000
  // materials took 80 s).
  std::unordered_map<std::string, size_t> index;
  for (size_t i = 0; i < out.size(); ++i) index.emplace(out[i].name, i);
  for (const MtlDefinition& d : defs) {
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

}  // namespace rayscout
