// The JSON document of a scene file and its material and transform values (json_fields.h).
#include "json_fields.h"

#include <algorithm>
#include <unordered_set>
#include <vector>

namespace rayscout::detail {
namespace {

// Builds the document from nlohmann's SAX events. Duplicate keys are rejected: nlohmann keeps
// the last of two equal keys, and a duplicate is a typo or a merge left over (unknown keys are
// errors for the same reason). Keys are appended to their object, not inserted through
// ordered_json's own parser, which finds each key by a linear search of the object (quadratic:
// an object of 100000 keys, a 1.2 MB file, took 31 s); the duplicate check uses a hash set.
class DocumentBuilder : public Json::json_sax_t {
 public:
  explicit DocumentBuilder(const std::string& file) : file_(file) {}

  Json take() { return std::move(root_); }

  bool null() override { return add(Json(nullptr)); }
  bool boolean(bool v) override { return add(Json(v)); }
  bool number_integer(number_integer_t v) override { return add(Json(v)); }
  bool number_unsigned(number_unsigned_t v) override { return add(Json(v)); }
  bool number_float(number_float_t v, const string_t&) override { return add(Json(v)); }
  bool string(string_t& v) override { return add(Json(std::move(v))); }
  bool binary(binary_t& v) override { return add(Json::binary(std::move(v))); }  // not in JSON text
  bool start_object(std::size_t) override {
    open_.push_back({Json::object(), {}, {}});
    return true;
  }
  bool key(string_t& k) override {
    Open& o = open_.back();
    if (!o.keys.insert(k).second)
      throw InputError(printable(file_ + ": key \"" + k + "\" appears twice in one object"));
    o.key = std::move(k);
    return true;
  }
  bool end_object() override { return close(); }
  bool start_array(std::size_t) override {
    open_.push_back({Json::array(), {}, {}});
    return true;
  }
  bool end_array() override { return close(); }
  // A syntax error, or out_of_range for a number like 1e400.
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& e) override {
    throw InputError(file_ + ": " + invalid_json(e.what()));
  }

 private:
  struct Open {  // an array or object being read, and for an object the key of the next value
    Json value;
    std::unordered_set<std::string> keys;
    std::string key;
  };

  bool add(Json v) {
    if (open_.empty()) {
      root_ = std::move(v);
    } else if (Open& o = open_.back(); o.value.is_array()) {
      o.value.get_ref<Json::array_t&>().push_back(std::move(v));
    } else {
      auto& members = static_cast<Json::object_t::Container&>(o.value.get_ref<Json::object_t&>());
      members.emplace_back(std::move(o.key), std::move(v));  // the key is new (checked in key())
    }
    return true;
  }
  bool close() {
    Json v = std::move(open_.back().value);
    open_.pop_back();
    return add(std::move(v));
  }

  const std::string& file_;
  std::vector<Open> open_;
  Json root_;
};

std::string format_vec3(const Vec3& v) {
  // Appended piece by piece: g++ 12 warns (-Wrestrict, a false positive) on "[" + string here.
  std::string s = "[";
  s += format_number(v.x);
  s += ", ";
  s += format_number(v.y);
  s += ", ";
  s += format_number(v.z);
  return s + "]";
}

// {"matrix": M}: 16 numbers or 4 rows of 4, row-major, last row 0 0 0 1, not singular.
Transform matrix_transform(const JsonFields& f, const Json& m, const std::string& mf) {
  std::vector<double> v;
  if (m.is_array() && m.size() == 16) {
    for (size_t i = 0; i < 16; ++i) v.push_back(f.number(m[i], JsonFields::index(mf, i)));
  } else if (m.is_array() && m.size() == 4) {
    for (size_t r = 0; r < 4; ++r) {
      if (!m[r].is_array() || m[r].size() != 4) f.fail(JsonFields::index(mf, r), "expected a row of 4 numbers");
      for (size_t c = 0; c < 4; ++c) v.push_back(f.number(m[r][c], JsonFields::index(JsonFields::index(mf, r), c)));
    }
  } else {
    f.fail(mf, "expected 16 numbers or 4 rows of 4 numbers (row-major)");
  }
  if (v[12] != 0 || v[13] != 0 || v[14] != 0 || v[15] != 1) f.fail(mf, "last row must be 0 0 0 1 (affine transforms only)");
  Transform t;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) t.m[r][c] = v[size_t(r * 4 + c)];
  // Float entries: the determinant is finite in double; 0 is the singular case.
  if (t.determinant() == 0) f.fail(mf, "matrix must not be singular (determinant 0 flattens the mesh)");
  return t;
}

// {"axis": [x, y, z], "deg": d}, or an array of them applied first to last.
Transform rotation(const JsonFields& f, const Json& rj, const std::string& rf) {
  const auto one = [&](const Json& x, const std::string& xf) {
    f.check_keys(x, xf, {"axis", "deg"});
    if (!x.contains("axis")) f.fail(JsonFields::join(xf, "axis"), "missing (rotation axis [x, y, z])");
    if (!x.contains("deg")) f.fail(JsonFields::join(xf, "deg"), "missing (rotation angle in degrees)");
    return Transform::rotate(f.direction(x["axis"], JsonFields::join(xf, "axis")), f.number(x["deg"], JsonFields::join(xf, "deg")));
  };
  if (!rj.is_array()) return one(rj, rf);
  Transform r;
  for (size_t i = 0; i < rj.size(); ++i) r = one(rj[i], JsonFields::index(rf, i)) * r;
  return r;
}

// Both lobes of a glossy material reflect: their sum, channel by channel, must stay <= 1.
void check_glossy_energy(const JsonFields& f, const std::string& field, const Material& m) {
  const Vec3 sum = m.diffuse + m.specular;
  const int i = sum.x >= sum.y && sum.x >= sum.z ? 0 : (sum.y >= sum.z ? 1 : 2);  // the largest
  if (sum[i] > 1.0f)
    f.fail(field, "diffuse + specular is " + format_number(sum[i]) + " in channel " + std::to_string(i) + " (diffuse " +
                      format_vec3(m.diffuse) + ", specular " + format_vec3(m.specular) +
                      "): a glossy material must have diffuse + specular <= 1 in every channel (more "
                      "would reflect more light than arrives)");
}

// One transform object: a "matrix", or scale, then rotate, then translate.
Transform parse_single_transform(const JsonFields& f, const Json& j, const std::string& field) {
  f.check_keys(j, field, {"translate", "scale", "rotate", "matrix"});
  if (j.contains("matrix")) {
    if (j.contains("translate") || j.contains("scale") || j.contains("rotate"))
      f.fail(field, "\"matrix\" cannot be combined with translate/scale/rotate");
    return matrix_transform(f, j["matrix"], JsonFields::join(field, "matrix"));
  }
  Transform s, r, t;
  if (j.contains("scale")) {
    const std::string sf = JsonFields::join(field, "scale");
    const Vec3 sc = j["scale"].is_number() ? Vec3(f.number(j["scale"], sf)) : f.vec3(j["scale"], sf);
    if (sc.x == 0 || sc.y == 0 || sc.z == 0) f.fail(sf, "scale must not be zero (it flattens the mesh)");
    s = Transform::scale(sc);
  }
  if (j.contains("rotate")) r = rotation(f, j["rotate"], JsonFields::join(field, "rotate"));
  if (j.contains("translate")) t = Transform::translate(f.vec3(j["translate"], JsonFields::join(field, "translate")));
  return t * r * s;
}

}  // namespace

Json read_json_document(const std::string& text, const std::string& file) {
  check_json_nesting(text, file);
  DocumentBuilder builder(file);
  Json::sax_parse(text, &builder);
  return builder.take();
}

void apply_material(const JsonFields& f, const Json& j, const std::string& field, Material& m, bool allow_name,
                    std::vector<std::string>& warnings) {
  if (allow_name) f.check_keys(j, field, {"name", "type", "diffuse", "specular", "exponent", "emission"});
  else f.check_keys(j, field, {"type", "diffuse", "specular", "exponent", "emission"});
  if (j.contains("type")) {
    const std::string t = f.string(j["type"], JsonFields::join(field, "type"));
    if (t == "diffuse") m.type = Material::Type::Diffuse;
    else if (t == "mirror") m.type = Material::Type::Mirror;
    else if (t == "glossy") m.type = Material::Type::Glossy;
    else f.fail(JsonFields::join(field, "type"), "expected \"diffuse\", \"mirror\" or \"glossy\", found \"" + t + "\"");
  }
  if (j.contains("diffuse")) m.diffuse = f.reflectance(j["diffuse"], JsonFields::join(field, "diffuse"));
  if (j.contains("specular")) m.specular = f.reflectance(j["specular"], JsonFields::join(field, "specular"));
  if (j.contains("exponent")) m.exponent = f.non_negative(j["exponent"], JsonFields::join(field, "exponent"));
  if (j.contains("emission")) m.emission = f.color(j["emission"], JsonFields::join(field, "emission"));
  // A mirror or glossy material without any specular colour would be black; give it one.
  const bool no_specular = m.specular.x == 0 && m.specular.y == 0 && m.specular.z == 0;
  if (m.type == Material::Type::Mirror && no_specular) m.specular = Vec3(1.0f);
  if (m.type == Material::Type::Glossy && no_specular) m.specular = Vec3(std::min(0.5f, 1.0f - max_component(m.diffuse)));
  if (m.type == Material::Type::Glossy && m.exponent == 0 && !j.contains("exponent")) m.exponent = 50.0f;
  if (m.type == Material::Type::Glossy) check_glossy_energy(f, field, m);
  // A field the type never reads most likely lacks its "type": {"specular": 0.5} alone stays
  // diffuse and rendered as plain diffuse, silently.
  const auto ignored = [&](const char* key, const char* type, const char* why) {
    if (j.contains(key))
      warnings.push_back(printable(f.file() + ": " + JsonFields::join(field, key) + ": ignored by a " + type +
                                   " material (" + why + ")"));
  };
  if (m.type == Material::Type::Diffuse) {
    ignored("specular", "diffuse", "give \"type\": \"glossy\" or \"mirror\" to use it");
    ignored("exponent", "diffuse", "give \"type\": \"glossy\" to use it");
  } else if (m.type == Material::Type::Mirror) {
    ignored("diffuse", "mirror", "a mirror has no diffuse lobe; \"type\": \"glossy\" has both");
    ignored("exponent", "mirror", "a mirror reflects in one direction; \"type\": \"glossy\" has a Phong lobe");
  }
}

Transform parse_transform(const JsonFields& f, const Json& j, const std::string& field) {
  if (j.is_array()) {
    Transform x;
    for (size_t i = 0; i < j.size(); ++i) x = parse_single_transform(f, j[i], JsonFields::index(field, i)) * x;
    return x;
  }
  return parse_single_transform(f, j, field);
}

}  // namespace rayscout::detail
