// JSON scene files: meshes and shapes with transforms, materials, camera and lights.
#include "json_scene.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <unordered_set>
#include <vector>

#include <nlohmann/json.hpp>

#include "rayscout/core/scenes_dir.h"
#include "rayscout/scene/load_scene.h"
#include "rayscout/scene/mesh.h"
#include "rayscout/scene/shapes.h"
#include "rayscout/scene/transform.h"
#include "scene_builder.h"
#include "text_parse.h"

namespace rayscout::detail {
namespace {

using Json = nlohmann::ordered_json;

// Typed access to JSON values; every error names the file and the field path.
class Fields {
 public:
  explicit Fields(std::string file) : file_(std::move(file)) {}

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
      if (is_comment(key)) continue;
      bool ok = false;
      for (const char* a : allowed) ok = ok || key == a;
      if (!ok) {
        std::string list;
        for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
        fail(join(field, key), "unknown key (expected one of: " + list + ")");
      }
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
    if (std::fabs(v) > kMaxCoordinate) fail(field, "is beyond +-1e11, where the ray-triangle test's products of three coordinates overflow float; scale the scene down");
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

std::string format_vec3(const Vec3& v) {
  return "[" + format_number(v.x) + ", " + format_number(v.y) + ", " + format_number(v.z) + "]";
}

// Applies the fields of a material object to m (omitted fields keep their value).
void apply_material(const Fields& f, const Json& j, const std::string& field, Material& m, bool allow_name) {
  if (allow_name) f.check_keys(j, field, {"name", "type", "diffuse", "specular", "exponent", "emission"});
  else f.check_keys(j, field, {"type", "diffuse", "specular", "exponent", "emission"});
  if (j.contains("type")) {
    const std::string t = f.string(j["type"], Fields::join(field, "type"));
    if (t == "diffuse") m.type = Material::Type::Diffuse;
    else if (t == "mirror") m.type = Material::Type::Mirror;
    else if (t == "glossy") m.type = Material::Type::Glossy;
    else f.fail(Fields::join(field, "type"), "expected \"diffuse\", \"mirror\" or \"glossy\", found \"" + t + "\"");
  }
  if (j.contains("diffuse")) m.diffuse = f.reflectance(j["diffuse"], Fields::join(field, "diffuse"));
  if (j.contains("specular")) m.specular = f.reflectance(j["specular"], Fields::join(field, "specular"));
  if (j.contains("exponent")) m.exponent = f.non_negative(j["exponent"], Fields::join(field, "exponent"));
  if (j.contains("emission")) m.emission = f.color(j["emission"], Fields::join(field, "emission"));
  // A mirror or glossy material without any specular colour would be black; give it one.
  const bool no_specular = m.specular.x == 0 && m.specular.y == 0 && m.specular.z == 0;
  if (m.type == Material::Type::Mirror && no_specular) m.specular = Vec3(1.0f);
  if (m.type == Material::Type::Glossy && no_specular) m.specular = Vec3(std::min(0.5f, 1.0f - max_component(m.diffuse)));
  if (m.type == Material::Type::Glossy && m.exponent == 0 && !j.contains("exponent")) m.exponent = 50.0f;
  // Both lobes of a glossy material reflect: their sum, channel by channel, must stay <= 1.
  if (m.type == Material::Type::Glossy) {
    const Vec3 sum = m.diffuse + m.specular;
    const int i = sum.x >= sum.y && sum.x >= sum.z ? 0 : (sum.y >= sum.z ? 1 : 2);  // the largest
    if (sum[i] > 1.0f)
      f.fail(field, "diffuse + specular is " + format_number(sum[i]) + " in channel " + std::to_string(i) +
                        " (diffuse " + format_vec3(m.diffuse) + ", specular " + format_vec3(m.specular) +
                        "): a glossy material must have diffuse + specular <= 1 in every channel (more "
                        "would reflect more light than arrives)");
  }
}

Transform parse_single_transform(const Fields& f, const Json& j, const std::string& field) {
  f.check_keys(j, field, {"translate", "scale", "rotate", "matrix"});
  if (j.contains("matrix")) {
    if (j.contains("translate") || j.contains("scale") || j.contains("rotate"))
      f.fail(field, "\"matrix\" cannot be combined with translate/scale/rotate");
    const Json& m = j["matrix"];
    const std::string mf = Fields::join(field, "matrix");
    std::vector<double> v;
    if (m.is_array() && m.size() == 16) {
      for (size_t i = 0; i < 16; ++i) v.push_back(f.number(m[i], Fields::index(mf, i)));
    } else if (m.is_array() && m.size() == 4) {
      for (size_t r = 0; r < 4; ++r) {
        if (!m[r].is_array() || m[r].size() != 4) f.fail(Fields::index(mf, r), "expected a row of 4 numbers");
        for (size_t c = 0; c < 4; ++c) v.push_back(f.number(m[r][c], Fields::index(Fields::index(mf, r), c)));
      }
    } else {
      f.fail(mf, "expected 16 numbers or 4 rows of 4 numbers (row-major)");
    }
    if (v[12] != 0 || v[13] != 0 || v[14] != 0 || v[15] != 1)
      f.fail(mf, "last row must be 0 0 0 1 (affine transforms only)");
    Transform t;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) t.m[r][c] = v[size_t(r * 4 + c)];
    // Float entries: the determinant is finite in double; 0 is the singular case.
    if (t.determinant() == 0) f.fail(mf, "matrix must not be singular (determinant 0 flattens the mesh)");
    return t;
  }
  Transform s, r, t;
  if (j.contains("scale")) {
    const std::string sf = Fields::join(field, "scale");
    const Vec3 sc = j["scale"].is_number() ? Vec3(f.number(j["scale"], sf)) : f.vec3(j["scale"], sf);
    if (sc.x == 0 || sc.y == 0 || sc.z == 0) f.fail(sf, "scale must not be zero (it flattens the mesh)");
    s = Transform::scale(sc);
  }
  if (j.contains("rotate")) {
    const Json& rj = j["rotate"];
    const std::string rf = Fields::join(field, "rotate");
    auto one = [&](const Json& x, const std::string& xf) {
      f.check_keys(x, xf, {"axis", "deg"});
      if (!x.contains("axis")) f.fail(Fields::join(xf, "axis"), "missing (rotation axis [x, y, z])");
      if (!x.contains("deg")) f.fail(Fields::join(xf, "deg"), "missing (rotation angle in degrees)");
      return Transform::rotate(f.direction(x["axis"], Fields::join(xf, "axis")), f.number(x["deg"], Fields::join(xf, "deg")));
    };
    if (rj.is_array()) {
      for (size_t i = 0; i < rj.size(); ++i) r = one(rj[i], Fields::index(rf, i)) * r;
    } else {
      r = one(rj, rf);
    }
  }
  if (j.contains("translate")) t = Transform::translate(f.vec3(j["translate"], Fields::join(field, "translate")));
  return t * r * s;
}

// An object (scale, then rotate, then translate) or an array of them applied first to last.
Transform parse_transform(const Fields& f, const Json& j, const std::string& field) {
  if (j.is_array()) {
    Transform x;
    for (size_t i = 0; i < j.size(); ++i) x = parse_single_transform(f, j[i], Fields::index(field, i)) * x;
    return x;
  }
  return parse_single_transform(f, j, field);
}

// One mesh to place: geometry, transform and an optional material that replaces its own.
struct Placement {
  std::shared_ptr<const Mesh> mesh;
  Transform transform;
  std::optional<Json> material;  // name or inline object
  std::string field;             // e.g. meshes[3]
  std::string source;            // for warnings: mesh file or shape
};

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

class JsonSceneLoader {
 public:
  explicit JsonSceneLoader(const std::filesystem::path& path) : path_(path), f_(display_name(path)) {}

  Scene load() {
    const Json root = parse_root(read_file(path_));
    f_.check_keys(root, "", {"meshes", "camera", "lights", "materials"});
    std::optional<CameraFields> camera;
    if (root.contains("camera")) camera = parse_camera(root["camera"]);

    std::vector<Placement> placements;
    for_each_in_array(root, "meshes", [&](const Json& j, const std::string& field) {
      placements.push_back(parse_mesh(j, field));
    });
    Scene scene;
    detail::SceneBuilder builder(scene);
    // Area lights are placed after all meshes (their triangles come last).
    for_each_in_array(root, "lights", [&](const Json& j, const std::string& field) {
      parse_light(j, field, scene, placements);
    });
    const auto maps = material_maps(root, placements, builder, scene);

    size_t total = 0;
    for (const auto& pl : placements) total += pl.mesh->faces.size();
    builder.reserve(total);
    // A mesh's warnings once, however often the mesh is placed. Looked up in a set: a search of
    // the list per warning was quadratic (an OBJ with 100000 undefined materials took 34 s).
    std::unordered_set<std::string> warned(scene.warnings.begin(), scene.warnings.end());
    for (size_t i = 0; i < placements.size(); ++i) {
      const auto& pl = placements[i];
      for (const auto& w : pl.mesh->warnings)
        if (warned.insert(w).second) scene.warnings.push_back(w);
      builder.add(*pl.mesh, pl.transform, maps[i], f_.file() + ": " + pl.field + " (" + pl.source + ")");
    }
    builder.finish(f_.file());
    warn_unused_materials(root, builder, scene);

    const Bounds3 bounds = scene.bounds();
    scene.camera = framing_camera(bounds, camera && camera->fov_deg ? *camera->fov_deg : 60.0f);
    apply_camera(camera.value_or(CameraFields{}), scene.camera);
    if (scene.point_lights.empty() && scene.emissive_triangles.empty()) {
      scene.point_lights.push_back(framing_light(bounds, scene.camera));
      scene.warnings.push_back(f_.file() + ": no lights; added a point light near the camera");
    }
    return scene;
  }

 private:
  // The document, with duplicate keys rejected (see DocumentBuilder).
  Json parse_root(const std::string& text) const {
    check_json_nesting(text, f_.file());
    DocumentBuilder builder(f_.file());
    Json::sax_parse(text, &builder);
    return builder.take();
  }

  // Calls fn(element, field) for each element of the array root[key], if present.
  template <class Fn>
  void for_each_in_array(const Json& root, const char* key, Fn&& fn) const {
    if (!root.contains(key)) return;
    const Json& a = root[key];
    if (!a.is_array()) f_.fail(key, std::string("expected an array, found ") + a.type_name());
    for (size_t i = 0; i < a.size(); ++i) fn(a[i], Fields::index(key, i));
  }

  // Per placement, the scene material of each of its mesh's materials: the meshes' own (first
  // definition of a name wins), then the "materials" overrides, then a placement's own
  // "material" (a name, or an inline object) for all of its triangles.
  std::vector<std::vector<uint32_t>> material_maps(const Json& root, const std::vector<Placement>& placements,
                                                   detail::SceneBuilder& builder, Scene& scene) {
    std::vector<std::vector<uint32_t>> maps(placements.size());
    for (size_t i = 0; i < placements.size(); ++i)
      if (!placements[i].material) maps[i] = builder.intern_all(*placements[i].mesh, placements[i].source, &scene.warnings);
    if (root.contains("materials")) {
      const Json& mats = root["materials"];
      f_.expect_object(mats, "materials");
      for (const auto& [name, value] : mats.items()) {
        if (Fields::is_comment(name)) continue;
        const std::string field = Fields::join("materials", name);
        Material m;
        if (auto existing = builder.find(name)) m = builder.material(*existing);
        m.name = name;
        apply_material(f_, value, field, m, false);
        builder.define(m);
      }
    }
    std::set<std::string> inline_names;
    for (size_t i = 0; i < placements.size(); ++i) {
      const auto& pl = placements[i];
      if (!pl.material) continue;
      const std::string field = Fields::join(pl.field, "material");
      uint32_t index;
      if (pl.material->is_string()) {
        const std::string name = pl.material->get<std::string>();
        auto found = builder.find(name);
        if (!found) f_.fail(field, "unknown material \"" + name + "\" (define it under \"materials\")");
        index = *found;
      } else if (pl.material->is_object()) {
        Material m;
        m.name = field;
        if (pl.material->contains("name")) m.name = f_.string((*pl.material)["name"], Fields::join(field, "name"));
        apply_material(f_, *pl.material, field, m, true);
        if (builder.find(m.name) || !inline_names.insert(m.name).second)
          f_.fail(Fields::join(field, "name"), "material \"" + m.name + "\" is already defined");
        index = builder.define(m);
      } else {
        f_.fail(field, std::string("expected a material name or object, found ") + pl.material->type_name());
      }
      maps[i].assign(pl.mesh->materials.size(), index);
    }
    return maps;
  }

  // A "materials" entry no triangle uses is most likely a misspelt override ("defualt").
  void warn_unused_materials(const Json& root, detail::SceneBuilder& builder, Scene& scene) const {
    if (!root.contains("materials")) return;
    std::vector<uint8_t> used(scene.materials.size(), 0);
    for (uint32_t id : scene.material_ids) used[id] = 1;
    for (const auto& [name, value] : root["materials"].items())
      if (auto index = builder.find(name); !Fields::is_comment(name) && index && !used[*index])
        scene.warnings.push_back(f_.file() + ": " + Fields::join("materials", name) +
                                 ": no triangle uses this material (a misspelt name?)");
  }

  std::filesystem::path resolve_path(const std::string& file) const {
    constexpr std::string_view prefix = "$RAYSCOUT_SCENES/";
    if (file.rfind(prefix, 0) == 0) return scenes_dir() / file.substr(prefix.size());
    std::filesystem::path p(file);
    if (p.is_relative()) p = path_.parent_path() / p;
    return p.lexically_normal();
  }

  // The same file listed several times is read once per load.
  std::shared_ptr<const Mesh> mesh_file(const Json& j, const std::string& field, std::string& source) {
    const std::filesystem::path p = resolve_path(f_.string(j, field));
    source = display_name(p);
    std::error_code ec;
    std::string key = std::filesystem::weakly_canonical(p, ec).string();
    if (ec) key = p.string();
    if (auto it = cache_.find(key); it != cache_.end()) return it->second;
    std::shared_ptr<const Mesh> mesh;
    try {
      mesh = std::make_shared<const Mesh>(read_mesh(p));
    } catch (const InputError& e) {
      throw InputError(f_.file() + ": " + field + ": " + e.what());
    }
    cache_.emplace(key, mesh);
    return mesh;
  }

  // A shape key that the chosen form does not use (a quad's "up" beside its corner, a box's "size")
  // is an error, as unknown keys are: it would be ignored.
  void check_form_keys(const Json& j, const std::string& field, const std::string& form,
                       std::initializer_list<std::string_view> used) const {
    for (const char* k : {"corner", "edge1", "edge2", "center", "normal", "size", "up", "min", "max"})
      if (j.contains(k) && std::find(used.begin(), used.end(), k) == used.end())
        f_.fail(Fields::join(field, k), "does not belong to " + form);
  }

  // A quad from corner + edge1 + edge2, or center + normal + size [+ up].
  std::shared_ptr<const Mesh> quad(const Json& j, const std::string& field) {
    if (j.contains("corner") || j.contains("edge1") || j.contains("edge2")) {
      for (const char* k : {"corner", "edge1", "edge2"})
        if (!j.contains(k)) f_.fail(Fields::join(field, k), "missing (a quad needs corner, edge1 and edge2)");
      check_form_keys(j, field, "a quad given by corner, edge1 and edge2", {"corner", "edge1", "edge2"});
      return std::make_shared<const Mesh>(make_quad(f_.vec3(j["corner"], Fields::join(field, "corner")),
                                                    f_.vec3(j["edge1"], Fields::join(field, "edge1")),
                                                    f_.vec3(j["edge2"], Fields::join(field, "edge2"))));
    }
    for (const char* k : {"center", "normal", "size"})
      if (!j.contains(k))
        f_.fail(Fields::join(field, k), "missing (a quad needs corner/edge1/edge2 or center/normal/size)");
    check_form_keys(j, field, "a quad given by center, normal and size", {"center", "normal", "size", "up"});
    const std::string sf = Fields::join(field, "size");
    float w, h;
    if (j["size"].is_number()) {
      w = h = f_.positive(j["size"], sf);
    } else {
      if (!j["size"].is_array() || j["size"].size() != 2) f_.fail(sf, "expected a number or [width, height]");
      w = f_.positive(j["size"][0], sf + "[0]");
      h = f_.positive(j["size"][1], sf + "[1]");
    }
    const Vec3 up = j.contains("up") ? f_.direction(j["up"], Fields::join(field, "up")) : Vec3(0, 1, 0);
    return std::make_shared<const Mesh>(make_quad_centered(f_.vec3(j["center"], Fields::join(field, "center")),
                                                           f_.direction(j["normal"], Fields::join(field, "normal")), w,
                                                           h, up));
  }

  std::shared_ptr<const Mesh> shape(const Json& j, const std::string& field, std::string& source) {
    const std::string kind = f_.string(j["shape"], Fields::join(field, "shape"));
    source = "shape " + kind;
    if (kind == "quad") return quad(j, field);
    if (kind == "box") {
      for (const char* k : {"min", "max"})
        if (!j.contains(k)) f_.fail(Fields::join(field, k), "missing (a box needs min and max)");
      check_form_keys(j, field, "a box (given by min and max)", {"min", "max"});
      const Vec3 lo = f_.vec3(j["min"], Fields::join(field, "min"));
      const Vec3 hi = f_.vec3(j["max"], Fields::join(field, "max"));
      if (!(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z)) f_.fail(Fields::join(field, "max"), "must exceed min on every axis");
      return std::make_shared<const Mesh>(make_box(lo, hi));
    }
    f_.fail(Fields::join(field, "shape"), "expected \"quad\" or \"box\", found \"" + kind + "\"");
  }

  Placement parse_mesh(const Json& j, const std::string& field) {
    f_.expect_object(j, field);
    Placement pl;
    pl.field = field;
    if (j.contains("file") == j.contains("shape")) f_.fail(field, "needs exactly one of \"file\" or \"shape\"");
    if (j.contains("file")) {
      f_.check_keys(j, field, {"file", "material", "transform"});
      pl.mesh = mesh_file(j["file"], Fields::join(field, "file"), pl.source);
    } else {
      f_.check_keys(j, field, {"shape", "material", "transform", "corner", "edge1", "edge2", "center", "normal",
                               "size", "up", "min", "max"});
      pl.mesh = shape(j, field, pl.source);
    }
    if (j.contains("transform")) pl.transform = parse_transform(f_, j["transform"], Fields::join(field, "transform"));
    if (j.contains("material")) pl.material = j["material"];
    return pl;
  }

  void parse_light(const Json& j, const std::string& field, Scene& scene, std::vector<Placement>& placements) {
    f_.expect_object(j, field);
    if (!j.contains("type")) f_.fail(Fields::join(field, "type"), "missing (\"point\" or \"area\")");
    const std::string type = f_.string(j["type"], Fields::join(field, "type"));
    if (type == "point") {
      f_.check_keys(j, field, {"type", "position", "intensity"});
      if (!j.contains("position")) f_.fail(Fields::join(field, "position"), "missing");
      PointLight l;
      l.position = f_.position(j["position"], Fields::join(field, "position"));
      if (j.contains("intensity")) l.intensity = f_.color(j["intensity"], Fields::join(field, "intensity"));
      // A dark light is a mistake that would give a silently black image (as for area lights).
      if (!(max_component(l.intensity) > 0)) f_.fail(Fields::join(field, "intensity"), "a point light must emit (> 0)");
      scene.point_lights.push_back(l);
      return;
    }
    if (type != "area") f_.fail(Fields::join(field, "type"), "expected \"point\" or \"area\", found \"" + type + "\"");
    f_.check_keys(j, field, {"type", "emission", "file", "shape", "transform", "corner", "edge1", "edge2", "center",
                             "normal", "size", "up", "min", "max"});
    if (!j.contains("emission")) f_.fail(Fields::join(field, "emission"), "missing (emitted radiance [r, g, b])");
    Placement pl;
    pl.field = field;
    if (j.contains("file")) {
      if (j.contains("shape")) f_.fail(field, "needs \"file\" or a shape, not both");
      check_form_keys(j, field, "an area light given by a file", {});
      pl.mesh = mesh_file(j["file"], Fields::join(field, "file"), pl.source);
    } else if (j.contains("shape")) {
      pl.mesh = shape(j, field, pl.source);
    } else {
      pl.source = "quad";
      pl.mesh = quad(j, field);
    }
    if (j.contains("transform")) pl.transform = parse_transform(f_, j["transform"], Fields::join(field, "transform"));
    const Vec3 e = f_.color(j["emission"], Fields::join(field, "emission"));
    if (e.x <= 0 && e.y <= 0 && e.z <= 0) f_.fail(Fields::join(field, "emission"), "an area light must emit (> 0)");
    pl.material = Json{{"diffuse", Json::array({0, 0, 0})}, {"emission", Json::array({e.x, e.y, e.z})}};
    placements.push_back(std::move(pl));
  }

  // Camera keys given in the file; the rest come from the framing camera.
  struct CameraFields {
    std::optional<Vec3> eye, look_at, up;
    std::optional<float> fov_deg, lens_radius, focus_distance;
  };

  CameraFields parse_camera(const Json& j) {
    f_.check_keys(j, "camera", {"eye", "look_at", "up", "fov_deg", "lens_radius", "focus_distance"});
    CameraFields c;
    if (j.contains("eye")) c.eye = f_.position(j["eye"], "camera.eye");
    if (j.contains("look_at")) c.look_at = f_.position(j["look_at"], "camera.look_at");
    if (j.contains("up")) c.up = f_.direction(j["up"], "camera.up");
    if (j.contains("fov_deg")) {
      c.fov_deg = f_.number(j["fov_deg"], "camera.fov_deg");
      if (!(*c.fov_deg > 0 && *c.fov_deg < 180)) f_.fail("camera.fov_deg", "expected a number in (0, 180)");
    }
    if (j.contains("lens_radius"))
      c.lens_radius = f_.bounded(f_.non_negative(j["lens_radius"], "camera.lens_radius"), "camera.lens_radius");
    if (j.contains("focus_distance"))
      c.focus_distance = f_.bounded(f_.positive(j["focus_distance"], "camera.focus_distance"), "camera.focus_distance");
    return c;
  }

  void apply_camera(const CameraFields& f, Camera& c) {
    if (f.eye) c.eye = *f.eye;
    if (f.look_at) c.look_at = *f.look_at;
    if (f.up) c.up = *f.up;
    if (f.fov_deg) c.fov_deg = *f.fov_deg;
    if (f.lens_radius) c.lens_radius = *f.lens_radius;
    // The framing camera backs off by radius / sin(fov / 2): a tiny fov_deg puts it out of reach.
    if (!f.eye) f_.bounded(max_component(abs(c.eye)), "camera.eye (the framing camera's, for this fov_deg; give an eye)");
    // Default: |look_at - eye|, in double so that neither a tiny nor a huge distance rounds to 0 or inf.
    const double dx = double(c.look_at.x) - c.eye.x, dy = double(c.look_at.y) - c.eye.y, dz = double(c.look_at.z) - c.eye.z;
    c.focus_distance = f.focus_distance ? *f.focus_distance : float(std::sqrt(dx * dx + dy * dy + dz * dz));
    if (!(c.focus_distance > 0))
      f_.fail("camera.focus_distance", "|look_at - eye| rounds to 0 in float; give a focus_distance");
    try {
      camera_frame(c, 1.0f);  // the frame every camera ray will use: "camera.up: is parallel ..."
    } catch (const InputError& e) {
      throw InputError(f_.file() + ": " + e.what());
    }
  }

  std::filesystem::path path_;
  Fields f_;
  std::map<std::string, std::shared_ptr<const Mesh>> cache_;
};

}  // namespace

Scene load_json_scene(const std::filesystem::path& path) { return JsonSceneLoader(path).load(); }

}  // namespace rayscout::detail
