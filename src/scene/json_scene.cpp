// JSON scene files: meshes and shapes with transforms, materials, camera and lights (schema in
// docs/scene-format.md). The values are read and checked through JsonFields (json_fields.h).
#include "json_scene.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <unordered_set>
#include <utility>
#include <vector>

#include "json_fields.h"
#include "rayscout/core/scenes_dir.h"
#include "rayscout/scene/load_scene.h"
#include "rayscout/scene/mesh.h"
#include "rayscout/scene/shapes.h"
#include "scene_builder.h"

namespace rayscout::detail {
namespace {

// A "file" that starts with this is read from the folder RAYSCOUT_SCENES names (scenes_dir()).
constexpr std::string_view kScenesPrefix = "$RAYSCOUT_SCENES/";

// One mesh to place: geometry, transform and an optional material that replaces its own.
struct Placement {
  std::shared_ptr<const Mesh> mesh;
  Transform transform;
  std::optional<Json> material;  // name or inline object
  std::string field;             // e.g. meshes[3]
  std::string source;            // for messages: mesh file or shape
};

// Camera keys given in the file; the rest come from the framing camera.
struct CameraFields {
  std::optional<Vec3> eye, look_at, up;
  std::optional<float> fov_deg, lens_radius, focus_distance;
};

class JsonSceneLoader {
 public:
  explicit JsonSceneLoader(const std::filesystem::path& path) : path_(path), f_(display_name(path)) {}

  Scene load() {
    const Json root = read_json_document(read_file(path_), f_.file());
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
    add_placements(placements, material_maps(root, placements, builder, scene), builder, scene);
    builder.finish(f_.file());
    warn_unused_materials(root, builder, scene);
    set_camera_and_default_light(camera, scene);
    return scene;
  }

  // Adds every placement's triangles in list order, its mesh's warnings once however often the
  // mesh is placed (looked up in a set: a search of the list per warning was quadratic, an OBJ
  // with 100000 undefined materials took 34 s).
  void add_placements(const std::vector<Placement>& placements, const std::vector<std::vector<uint32_t>>& maps,
                      detail::SceneBuilder& builder, Scene& scene) const {
    size_t total = 0;
    for (const auto& pl : placements) total += pl.mesh->faces.size();
    builder.reserve(total);
    std::unordered_set<std::string> warned(scene.warnings.begin(), scene.warnings.end());
    for (size_t i = 0; i < placements.size(); ++i) {
      const auto& pl = placements[i];
      for (const auto& w : pl.mesh->warnings)
        if (warned.insert(w).second) scene.warnings.push_back(w);
      builder.add(*pl.mesh, pl.transform, maps[i], f_.file() + ": " + pl.field + " (" + pl.source + ")");
    }
  }

  // The file's camera keys over the framing camera of the finished scene; the framing point light
  // (with a warning) when the scene has no light.
  void set_camera_and_default_light(const std::optional<CameraFields>& camera, Scene& scene) {
    const Bounds3 bounds = scene.bounds();
    scene.camera = framing_camera(bounds, camera && camera->fov_deg ? *camera->fov_deg : 60.0f);
    apply_camera(camera.value_or(CameraFields{}), scene.camera);
    if (scene.point_lights.empty() && scene.emissive_triangles.empty()) {
      scene.point_lights.push_back(framing_light(bounds, scene.camera));
      scene.warnings.push_back(f_.file() + ": no lights; added a point light near the camera");
    }
  }

  // Calls fn(element, field) for each element of the array root[key], if present.
  template <class Fn>
  void for_each_in_array(const Json& root, const char* key, Fn&& fn) const {
    if (!root.contains(key)) return;
    const Json& a = root[key];
    if (!a.is_array()) f_.fail(key, std::string("expected an array, found ") + a.type_name());
    for (size_t i = 0; i < a.size(); ++i) fn(a[i], JsonFields::index(key, i));
  }

  // Per placement, the scene material of each of its mesh's materials: the meshes' own (first
  // definition of a name wins), then the "materials" overrides, then a placement's own
  // "material" (a name, or an inline object) for all of its triangles.
  std::vector<std::vector<uint32_t>> material_maps(const Json& root, const std::vector<Placement>& placements,
                                                   detail::SceneBuilder& builder, Scene& scene) {
    std::vector<std::vector<uint32_t>> maps(placements.size());
    for (size_t i = 0; i < placements.size(); ++i)
      if (!placements[i].material) maps[i] = builder.intern_all(*placements[i].mesh, placements[i].source, &scene.warnings);
    if (root.contains("materials")) define_materials(root["materials"], builder, scene.warnings);
    for (size_t i = 0; i < placements.size(); ++i)
      if (placements[i].material)
        maps[i].assign(placements[i].mesh->materials.size(),
                       placement_material(placements[i], builder, scene.warnings));
    return maps;
  }

  // The "materials" entries: each overrides the fields it gives of a material of that name, or
  // defines a new one.
  void define_materials(const Json& mats, detail::SceneBuilder& builder, std::vector<std::string>& warnings) const {
    f_.expect_object(mats, "materials");
    for (const auto& [name, value] : mats.items()) {
      if (JsonFields::is_comment(name)) continue;
      if (name.empty()) f_.fail("materials", "a material name must not be empty");
      Material m;
      if (auto existing = builder.find(name)) m = builder.material(*existing);
      m.name = name;
      apply_material(f_, value, JsonFields::join("materials", name), m, false, warnings);
      builder.define(m);
    }
  }

  // What an unknown material name may have meant: the defined name closest to it when it is a
  // likely typo ("flor" for "floor"), else the defined names, so that the user can pick one.
  static std::string material_hint(const std::string& name, const detail::SceneBuilder& builder) {
    const auto& mats = builder.materials();
    if (mats.empty()) return "no material is defined: define it under \"materials\"";
    const auto lower = [](char c) { return char(std::tolower((unsigned char)c)); };
    const auto distance = [&](const std::string& a, const std::string& b) {  // Levenshtein, case-insensitive
      std::vector<size_t> row(b.size() + 1);
      for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
      for (size_t i = 1; i <= a.size(); ++i) {
        size_t diag = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j)
          diag = std::exchange(row[j], std::min({row[j] + 1, row[j - 1] + 1, diag + (lower(a[i - 1]) != lower(b[j - 1]))}));
      }
      return row[b.size()];
    };
    const Material* best = nullptr;
    size_t best_distance = std::max<size_t>(1, name.size() / 3) + 1;  // more edits than a third: no typo
    for (const Material& m : mats)
      if (m.name.size() < 256 && name.size() < 256)
        if (const size_t d = distance(name, m.name); d < best_distance) best = &m, best_distance = d;
    if (best) return "did you mean \"" + best->name + "\"?";
    std::string names;
    const size_t shown = std::min<size_t>(mats.size(), 8);
    for (size_t i = 0; i < shown; ++i) names += (i ? ", \"" : "\"") + mats[i].name + "\"";
    return "defined: " + names + (mats.size() > shown ? " and " + std::to_string(mats.size() - shown) + " more" : "") +
           "; define it under \"materials\"";
  }

  // The scene material of a placement's own "material": a defined name, or an inline object that
  // defines a new one (named meshes[i].material unless it has a "name").
  uint32_t placement_material(const Placement& pl, detail::SceneBuilder& builder,
                              std::vector<std::string>& warnings) const {
    const std::string field = JsonFields::join(pl.field, "material");
    if (pl.material->is_string()) {
      const std::string name = pl.material->get<std::string>();
      const auto found = builder.find(name);
      if (!found) f_.fail(field, "unknown material \"" + name + "\" (" + material_hint(name, builder) + ")");
      return *found;
    }
    if (!pl.material->is_object())
      f_.fail(field, std::string("expected a material name or object, found ") + pl.material->type_name());
    Material m;
    m.name = field;
    if (pl.material->contains("name")) {
      m.name = f_.string((*pl.material)["name"], JsonFields::join(field, "name"));
      if (m.name.empty()) f_.fail(JsonFields::join(field, "name"), "a material name must not be empty");
    }
    apply_material(f_, *pl.material, field, m, true, warnings);
    if (builder.find(m.name)) f_.fail(JsonFields::join(field, "name"), "material \"" + m.name + "\" is already defined");
    return builder.define(m);
  }

  // A "materials" entry no triangle uses is most likely a misspelt override ("defualt").
  void warn_unused_materials(const Json& root, detail::SceneBuilder& builder, Scene& scene) const {
    if (!root.contains("materials")) return;
    std::vector<uint8_t> used(scene.materials.size(), 0);
    for (uint32_t id : scene.material_ids) used[id] = 1;
    for (const auto& [name, value] : root["materials"].items())
      if (auto index = builder.find(name); !JsonFields::is_comment(name) && index && !used[*index])
        scene.warnings.push_back(printable(f_.file() + ": " + JsonFields::join("materials", name) +
                                           ": no triangle uses this material (a misspelt name?)"));
  }

  // A missing "$RAYSCOUT_SCENES/..." file most often means the variable points elsewhere.
  static std::string scenes_dir_hint(const std::string& file, const std::filesystem::path& resolved) {
    std::error_code ec;
    if (!file.starts_with(kScenesPrefix) || std::filesystem::exists(resolved, ec)) return "";
    return " (\"" + file + "\": " + scenes_dir_origin() + "; set RAYSCOUT_SCENES to the folder that holds the scenes)";
  }

  std::filesystem::path resolve_path(const std::string& file) const {
    if (file.starts_with(kScenesPrefix)) return scenes_dir() / file.substr(kScenesPrefix.size());
    std::filesystem::path p(file);
    if (p.is_relative()) p = path_.parent_path() / p;
    return p.lexically_normal();
  }

  // The same file listed several times is read once per load. Every "file" (meshes and area
  // lights) comes through here.
  std::shared_ptr<const Mesh> mesh_file(const Json& j, const std::string& field, std::string& source) {
    const std::string name = f_.string(j, field);
    if (name.empty()) f_.fail(field, "empty file name");
    // The OS reads a path up to its first NUL: "ok.obj\u0000junk.obj" loaded ok.obj.
    if (name.find('\0') != std::string::npos)
      f_.fail(field, "file name \"" + name + "\" holds a NUL character (\\u0000), which no file name can contain");
    const std::filesystem::path p = resolve_path(name);
    source = display_name(p);
    const std::string key = same_file_key(p);
    if (auto it = cache_.find(key); it != cache_.end()) return it->second;
    std::shared_ptr<const Mesh> mesh;
    try {
      mesh = std::make_shared<const Mesh>(read_mesh(p));
    } catch (const InputError& e) {
      throw InputError(printable(f_.file() + ": " + field + ": " + e.what() + scenes_dir_hint(name, p)));
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
        f_.fail(JsonFields::join(field, k), "does not belong to " + form);
  }

  // A quad from corner + edge1 + edge2, or center + normal + size [+ up].
  std::shared_ptr<const Mesh> quad(const Json& j, const std::string& field) const {
    const bool by_corner = j.contains("corner") || j.contains("edge1") || j.contains("edge2");
    return std::make_shared<const Mesh>(by_corner ? corner_quad(j, field) : centred_quad(j, field));
  }

  Mesh corner_quad(const Json& j, const std::string& field) const {
    for (const char* k : {"corner", "edge1", "edge2"})
      if (!j.contains(k)) f_.fail(JsonFields::join(field, k), "missing (a quad needs corner, edge1 and edge2)");
    check_form_keys(j, field, "a quad given by corner, edge1 and edge2", {"corner", "edge1", "edge2"});
    return make_quad(f_.vec3(j["corner"], JsonFields::join(field, "corner")),
                     f_.vec3(j["edge1"], JsonFields::join(field, "edge1")),
                     f_.vec3(j["edge2"], JsonFields::join(field, "edge2")));
  }

  Mesh centred_quad(const Json& j, const std::string& field) const {
    for (const char* k : {"center", "normal", "size"})
      if (!j.contains(k))
        f_.fail(JsonFields::join(field, k), "missing (a quad needs corner/edge1/edge2 or center/normal/size)");
    check_form_keys(j, field, "a quad given by center, normal and size", {"center", "normal", "size", "up"});
    const std::string sf = JsonFields::join(field, "size");
    float w, h;
    if (j["size"].is_number()) {
      w = h = f_.positive(j["size"], sf);
    } else {
      if (!j["size"].is_array() || j["size"].size() != 2) f_.fail(sf, "expected a number or [width, height]");
      w = f_.positive(j["size"][0], sf + "[0]");
      h = f_.positive(j["size"][1], sf + "[1]");
    }
    const Vec3 up = j.contains("up") ? f_.direction(j["up"], JsonFields::join(field, "up")) : Vec3(0, 1, 0);
    return make_quad_centered(f_.vec3(j["center"], JsonFields::join(field, "center")),
                              f_.direction(j["normal"], JsonFields::join(field, "normal")), w, h, up);
  }

  std::shared_ptr<const Mesh> shape(const Json& j, const std::string& field, std::string& source) {
    const std::string kind = f_.string(j["shape"], JsonFields::join(field, "shape"));
    source = "shape " + kind;
    if (kind == "quad") return quad(j, field);
    if (kind == "box") {
      for (const char* k : {"min", "max"})
        if (!j.contains(k)) f_.fail(JsonFields::join(field, k), "missing (a box needs min and max)");
      check_form_keys(j, field, "a box (given by min and max)", {"min", "max"});
      const Vec3 lo = f_.vec3(j["min"], JsonFields::join(field, "min"));
      const Vec3 hi = f_.vec3(j["max"], JsonFields::join(field, "max"));
      if (!(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z)) f_.fail(JsonFields::join(field, "max"), "must exceed min on every axis");
      return std::make_shared<const Mesh>(make_box(lo, hi));
    }
    f_.fail(JsonFields::join(field, "shape"), "expected \"quad\" or \"box\", found \"" + kind + "\"");
  }

  Placement parse_mesh(const Json& j, const std::string& field) {
    f_.expect_object(j, field);
    Placement pl;
    pl.field = field;
    if (j.contains("file") == j.contains("shape")) f_.fail(field, "needs exactly one of \"file\" or \"shape\"");
    if (j.contains("file")) {
      f_.check_keys(j, field, {"file", "material", "transform"});
      pl.mesh = mesh_file(j["file"], JsonFields::join(field, "file"), pl.source);
    } else {
      f_.check_keys(j, field, {"shape", "material", "transform", "corner", "edge1", "edge2", "center", "normal",
                               "size", "up", "min", "max"});
      pl.mesh = shape(j, field, pl.source);
    }
    if (j.contains("transform")) pl.transform = parse_transform(f_, j["transform"], JsonFields::join(field, "transform"));
    if (j.contains("material")) pl.material = j["material"];
    return pl;
  }

  void parse_light(const Json& j, const std::string& field, Scene& scene, std::vector<Placement>& placements) {
    f_.expect_object(j, field);
    if (!j.contains("type")) f_.fail(JsonFields::join(field, "type"), "missing (\"point\" or \"area\")");
    const std::string type = f_.string(j["type"], JsonFields::join(field, "type"));
    if (type == "point") scene.point_lights.push_back(point_light(j, field));
    else if (type == "area") placements.push_back(area_light(j, field));
    else f_.fail(JsonFields::join(field, "type"), "expected \"point\" or \"area\", found \"" + type + "\"");
  }

  PointLight point_light(const Json& j, const std::string& field) const {
    f_.check_keys(j, field, {"type", "position", "intensity"});
    if (!j.contains("position")) f_.fail(JsonFields::join(field, "position"), "missing");
    PointLight l;
    l.position = f_.position(j["position"], JsonFields::join(field, "position"));
    if (j.contains("intensity")) l.intensity = f_.color(j["intensity"], JsonFields::join(field, "intensity"));
    // A dark light is a mistake that would give a silently black image (as for area lights).
    if (!(max_component(l.intensity) > 0)) f_.fail(JsonFields::join(field, "intensity"), "a point light must emit (> 0)");
    return l;
  }

  // An area light's geometry (a file, a shape, or a quad's keys) with a black emitting material.
  Placement area_light(const Json& j, const std::string& field) {
    f_.check_keys(j, field, {"type", "emission", "file", "shape", "transform", "corner", "edge1", "edge2", "center",
                             "normal", "size", "up", "min", "max"});
    if (!j.contains("emission")) f_.fail(JsonFields::join(field, "emission"), "missing (emitted radiance [r, g, b])");
    Placement pl;
    pl.field = field;
    if (j.contains("file")) {
      if (j.contains("shape")) f_.fail(field, "needs \"file\" or a shape, not both");
      check_form_keys(j, field, "an area light given by a file", {});
      pl.mesh = mesh_file(j["file"], JsonFields::join(field, "file"), pl.source);
    } else if (j.contains("shape")) {
      pl.mesh = shape(j, field, pl.source);
    } else {
      pl.source = "quad";
      pl.mesh = quad(j, field);
    }
    if (j.contains("transform")) pl.transform = parse_transform(f_, j["transform"], JsonFields::join(field, "transform"));
    const Vec3 e = f_.color(j["emission"], JsonFields::join(field, "emission"));
    if (e.x <= 0 && e.y <= 0 && e.z <= 0) f_.fail(JsonFields::join(field, "emission"), "an area light must emit (> 0)");
    pl.material = Json{{"diffuse", Json::array({0, 0, 0})}, {"emission", Json::array({e.x, e.y, e.z})}};
    return pl;
  }

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
    // The frame first: eye == look_at is "camera.look_at: must differ from camera.eye", not a
    // focus distance that rounds to 0 (which asked for a focus_distance that did not help).
    try {
      camera_frame(c, 1.0f);  // the frame every camera ray will use: "camera.up: is parallel ..."
    } catch (const InputError& e) {
      // A key the file does not give holds its default, which the message must name: a camera
      // looking straight down with the default up said only that camera.up is parallel.
      std::string what = e.what();
      if (!f.up && what.starts_with("camera.up: is parallel"))
        what += " (camera.up is not given and defaults to [0, 1, 0]: give one across the view, such as [0, 0, -1] "
                "for a camera looking straight down)";
      if (!f.look_at && what.starts_with("camera.look_at: must differ"))
        what += " (camera.look_at is not given and defaults to the centre of the bounds, (" + format_number(c.look_at.x) +
                ", " + format_number(c.look_at.y) + ", " + format_number(c.look_at.z) + "): give one)";
      throw InputError(f_.file() + ": " + what);
    }
    // Default: |look_at - eye|, in double so that neither a tiny nor a huge distance rounds to 0 or inf.
    const double dx = double(c.look_at.x) - c.eye.x, dy = double(c.look_at.y) - c.eye.y, dz = double(c.look_at.z) - c.eye.z;
    c.focus_distance = f.focus_distance ? *f.focus_distance : float(std::sqrt(dx * dx + dy * dy + dz * dz));
    if (!(c.focus_distance > 0))
      f_.fail("camera.focus_distance", "|look_at - eye| rounds to 0 in float; give a focus_distance");
  }

  std::filesystem::path path_;
  JsonFields f_;
  std::map<std::string, std::shared_ptr<const Mesh>> cache_;
};

}  // namespace

Scene load_json_scene(const std::filesystem::path& path) { return JsonSceneLoader(path).load(); }

}  // namespace rayscout::detail
