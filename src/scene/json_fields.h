// Reading the JSON of scene files: the document (duplicate keys rejected) and typed access to its
// values, where every error names the file and the field path ("scene.json: meshes[2].transform.
// scale: scale must not be zero"); plus the two value kinds a scene repeats, materials and
// transforms. The schema is in docs/scene-format.md.
#pragma once

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rayscout/core/input_error.h"
#include "rayscout/scene/scene.h"
#include "rayscout/scene/transform.h"
#include "scene_builder.h"
#include "text_parse.h"

namespace rayscout::detail {

using Json = nlohmann::ordered_json;

/// The document in `text` of `file`; a syntax error, a number out of range or a key that
/// appears twice in one object throws InputError naming the file.
Json read_json_document(const std::string& text, const std::string& file);

/// Typed access to JSON values; every error names the file and the field path.
class JsonFields {
 public:
  explicit JsonFields(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& field, const std::string& msg) const {
    throw InputError(printable(file_ + ": " + (field.empty() ? std::string("(root)") : field) + ": " + msg));
  }
  const std::string& file() const { return file_; }

  // "comment" is allowed in every object, also where keys are names (materials).
  static bool is_comment(const std::string& key) { return key == "comment"; }

  // Unknown keys are errors, so typos are caught; comments are allowed everywhere.
  void check_keys(const Json& obj, const std::string& field, std::initializer_list<const char*> allowed) const {
    expect_object(obj, field);
    for (const auto& [key, value] : obj.items()) {
      if (is_comment(key) || std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
      std::string list;
      for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
      if (key.empty()) fail(field, "unknown empty key \"\" (expected one of: " + list + ")");
      fail(join(field, key), "unknown key (expected one of: " + list + ")");
    }
  }
  void expect_object(const Json& j, const std::string& field) const {
    if (!j.is_object()) fail(field, std::string("expected an object, found ") + j.type_name());
  }
  float number(const Json& j, const std::string& field) const {
    if (!j.is_number()) fail(field, std::string("expected a number, found ") + j.type_name());
    const double d = j.get<double>();
    if (!std::isfinite(float(d))) fail(field, "number is not finite in single precision");
    return float(d);
  }
  float positive(const Json& j, const std::string& field) const {
    const float v = number(j, field);
    if (!(v > 0)) fail(field, "expected a positive number");
    return v;
  }
  float non_negative(const Json& j, const std::string& field) const {
    const float v = number(j, field);
    if (v < 0) fail(field, "expected a number >= 0");
    return v;
  }
  std::string string(const Json& j, const std::string& field) const {
    if (!j.is_string()) fail(field, std::string("expected a string, found ") + j.type_name());
    return j.get<std::string>();
  }
  Vec3 vec3(const Json& j, const std::string& field) const {
    if (!j.is_array() || j.size() != 3) fail(field, "expected an array of 3 numbers [x, y, z]");
    return {number(j[0], field + "[0]"), number(j[1], field + "[1]"), number(j[2], field + "[2]")};
  }
  // Points and lengths the renderer squares (distances, falloff): bounded like vertices.
  float bounded(float v, const std::string& field) const {
    if (std::fabs(v) > kMaxCoordinate) fail(field, std::string(kBeyondMaxCoordinate));
    return v;
  }
  Vec3 position(const Json& j, const std::string& field) const {
    const Vec3 p = vec3(j, field);
    bounded(max_component(abs(p)), field);
    return p;
  }
  Vec3 direction(const Json& j, const std::string& field) const {
    const Vec3 v = vec3(j, field);
    if (v.x == 0 && v.y == 0 && v.z == 0) fail(field, "direction must not be zero");
    return v;
  }
  // A colour: [r, g, b] or one number for grey; components >= 0.
  Vec3 color(const Json& j, const std::string& field) const {
    const Vec3 c = j.is_number() ? Vec3(number(j, field)) : vec3(j, field);
    if (c.x < 0 || c.y < 0 || c.z < 0) fail(field, "colour components must be >= 0");
    return c;
  }
  // A reflectance: a colour with components in [0, 1].
  Vec3 reflectance(const Json& j, const std::string& field) const {
    const Vec3 c = color(j, field);
    for (int i = 0; i < 3; ++i)
      if (c[i] > 1.0f)
        fail(field, format_number(c[i]) + " is above 1: a reflectance must be in [0, 1] (more would reflect more "
                    "light than arrives)");
    return c;
  }
  static std::string join(const std::string& field, const std::string& key) {
    return field.empty() ? key : field + "." + key;
  }
  static std::string index(const std::string& field, size_t i) { return field + "[" + std::to_string(i) + "]"; }

 private:
  std::string file_;
};

/// Applies the fields of a material object to m (omitted fields keep their value); a field that
/// m's type does not read (specular on a diffuse material, ...) adds a warning.
void apply_material(const JsonFields& f, const Json& j, const std::string& field, Material& m, bool allow_name,
                    std::vector<std::string>& warnings);

/// A transform object (scale, then rotate, then translate, or a "matrix") or an array of them
/// applied first to last.
Transform parse_transform(const JsonFields& f, const Json& j, const std::string& field);

}  // namespace rayscout::detail
