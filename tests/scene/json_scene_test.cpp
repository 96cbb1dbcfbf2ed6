// JSON scene files: meshes, material overrides, shapes, transforms, camera, lights, caching.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "rayscout/scene/load_scene.h"
#include "temp_files.h"

namespace rayscout {
namespace {

using testing::TempDir;

void expect_near(const Vec3& a, const Vec3& b, float tol = 1e-6f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

// Two quads: "floor" (y = 0) and "wall" (z = 0), from an OBJ with an MTL.
void write_room(const TempDir& dir) {
  dir.write("room.mtl", "newmtl floor\nKd 0.5 0.5 0.5\nnewmtl wall\nKd 0.2 0.3 0.4\nKs 0.1 0.1 0.1\nNs 20\n");
  dir.write("room.obj",
            "mtllib room.mtl\nv -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nv -1 0 -1\nv 1 0 -1\nv 1 2 -1\nv -1 2 -1\n"
            "usemtl floor\nf 1 4 3 2\nusemtl wall\nf 5 6 7 8\n");
}

TEST(JsonScene, MaterialOverrideMakesTheFloorAMirror) {
  TempDir dir;
  write_room(dir);
  const Scene s = load_scene(dir.write("scene.json", R"({
    "meshes": [{"file": "room.obj"}],
    "materials": {"floor": {"type": "mirror", "specular": [0.9, 0.9, 0.9]},
                  "wall": {"emission": 2}}
  })"));
  ASSERT_EQ(s.triangles.size(), 4u);
  const Material& floor = s.material_of(0);
  EXPECT_EQ(floor.name, "floor");
  EXPECT_EQ(floor.type, Material::Type::Mirror);
  expect_near(floor.specular, Vec3(0.9f));
  expect_near(floor.diffuse, Vec3(0.5f));  // omitted fields keep the MTL values
  const Material& wall = s.material_of(2);
  EXPECT_EQ(wall.type, Material::Type::Glossy);
  EXPECT_EQ(wall.exponent, 20.0f);
  expect_near(wall.emission, Vec3(2.0f));
  EXPECT_EQ(s.emissive_triangles, (std::vector<uint32_t>{2, 3}));
  EXPECT_EQ(s.materials.size(), 2u);
}

TEST(JsonScene, MeshMaterialByNameOrInline) {
  TempDir dir;
  write_room(dir);
  const Scene s = load_scene(dir.write("scene.json", R"({
    "materials": {"gold": {"type": "glossy", "diffuse": [0.3, 0.2, 0.1], "specular": [0.7, 0.6, 0.2], "exponent": 100}},
    "meshes": [{"file": "room.obj", "material": "gold"},
               {"file": "room.obj", "material": {"type": "mirror"}},
               {"file": "room.obj"}]
  })"));
  ASSERT_EQ(s.triangles.size(), 12u);
  for (uint32_t t = 0; t < 4; ++t) EXPECT_EQ(s.material_of(t).name, "gold");
  EXPECT_EQ(s.material_of(0).exponent, 100.0f);
  EXPECT_EQ(s.material_of(4).name, "meshes[1].material");
  EXPECT_EQ(s.material_of(4).type, Material::Type::Mirror);
  expect_near(s.material_of(4).specular, Vec3(1.0f));  // a mirror without specular gets 1
  EXPECT_EQ(s.material_of(8).name, "floor");
  EXPECT_EQ(s.material_of(10).name, "wall");
}

// Only a normal's direction matters: a tiny one (its squared length underflows float) made
// the quad's vertices NaN ("vertex 0 is not finite").
TEST(JsonScene, QuadNormalOfAnyLength) {
  TempDir dir;
  for (const char* normal : {"[1e-30, 0, 0]", "[3e38, 0, 0]", "[1, 0, 0]"}) {
    const Scene s = load_scene(dir.write("q.json", std::string(R"({"meshes": [{"shape": "quad", "center": [0, 0, 0],
        "normal": )") + normal + R"(, "size": 1}]})"));
    ASSERT_EQ(s.triangles.size(), 2u) << normal;
    expect_near(normalize(s.triangles[0].normal()), {1, 0, 0});
  }
}

// The same for a quad's up: a short one not parallel to the normal was taken for parallel (its
// projection fell below an absolute 1e-6), so the height ran along z, not along the up asked for.
TEST(JsonScene, QuadUpOfAnyLength) {
  TempDir dir;
  for (const char* up : {"[1e-7, 1e-7, 0]", "[1e20, 1e20, 0]", "[1, 1, 0]"}) {
    const Scene s = load_scene(dir.write("q.json", std::string(R"({"meshes": [{"shape": "quad", "center": [0, 0, 0],
        "normal": [0, 1, 0], "size": [4, 1], "up": )") + up + "}]}"));
    ASSERT_EQ(s.triangles.size(), 2u) << up;
    const Bounds3 b = s.bounds();  // 4 wide along z, 1 high along x
    expect_near(b.lo, {-0.5f, 0, -2}, 1e-6f);
    expect_near(b.hi, {0.5f, 0, 2}, 1e-6f);
  }
}

TEST(JsonScene, ShapesWithExactVertices) {
  TempDir dir;
  const Scene s = load_scene(dir.write("shapes.json", R"({
    "meshes": [
      {"shape": "quad", "corner": [1, 2, 3], "edge1": [2, 0, 0], "edge2": [0, 0, -4], "material": {"name": "m1"}},
      {"shape": "quad", "center": [0, 0, 0], "normal": [0, 1, 0], "size": [2, 4], "up": [0, 0, -1]},
      {"shape": "box", "min": [-1, -2, -3], "max": [1, 2, 3]}
    ]})"));
  ASSERT_EQ(s.triangles.size(), 2u + 2u + 12u);
  const Triangle& q0 = s.triangles[0];
  expect_near(q0.v0, {1, 2, 3}, 0);
  expect_near(q0.v1, {3, 2, 3}, 0);
  expect_near(q0.v2, {3, 2, -1}, 0);
  expect_near(s.triangles[1].v2, {1, 2, -1}, 0);
  expect_near(normalize(q0.normal()), {0, 1, 0});  // edge1 x edge2
  // Centered quad: 2 wide (x), 4 high (along up = -z), facing +y.
  Bounds3 b1;
  b1.extend(s.triangles[2].bounds());
  b1.extend(s.triangles[3].bounds());
  expect_near(b1.lo, {-1, 0, -2});
  expect_near(b1.hi, {1, 0, 2});
  expect_near(normalize(s.triangles[2].normal()), {0, 1, 0});
  // Box: bounds and outward normals (every normal points away from the centre).
  Bounds3 box;
  for (size_t t = 4; t < 16; ++t) {
    box.extend(s.triangles[t].bounds());
    EXPECT_GT(dot(s.triangles[t].normal(), s.triangles[t].centroid()), 0.0f) << "triangle " << t;
  }
  expect_near(box.lo, {-1, -2, -3}, 0);
  expect_near(box.hi, {1, 2, 3}, 0);
}

// "comment" was taken for a material name in "materials" ("expected an object, found string").
TEST(JsonScene, CommentIsAllowedInMaterials) {
  TempDir dir;
  write_room(dir);
  const Scene s = load_scene(dir.write("scene.json", R"({
    "meshes": [{"file": "room.obj"}],
    "materials": {"comment": "the floor becomes a mirror", "floor": {"comment": "polished", "type": "mirror"}}})"));
  ASSERT_EQ(s.triangles.size(), 4u);
  EXPECT_EQ(s.material_of(0).name, "floor");
  EXPECT_EQ(s.material_of(0).type, Material::Type::Mirror);
  ASSERT_EQ(s.materials.size(), 2u);  // floor and wall, no material "comment"
  EXPECT_EQ(s.materials[1].name, "wall");
  for (const auto& w : s.warnings) EXPECT_EQ(w.find("comment"), std::string::npos) << w;
}

// An override whose name no mesh uses is most likely misspelt: it is kept, with a warning.
TEST(JsonScene, UnusedMaterialWarns) {
  TempDir dir;
  write_room(dir);
  const Scene s = load_scene(dir.write("scene.json", R"({
    "meshes": [{"file": "room.obj"}],
    "materials": {"flor": {"type": "mirror"}, "wall": {"emission": 2}}})"));
  size_t unused = 0;
  for (const auto& w : s.warnings) {
    if (w.find("materials.flor: no triangle uses this material") != std::string::npos) ++unused;
    EXPECT_EQ(w.find("materials.wall"), std::string::npos) << w;
  }
  EXPECT_EQ(unused, 1u);
}

// A field the material's type never reads is said: {"specular": 0.5} without "type" stayed a
// plain diffuse material, silently; an MTL material overridden keeps its type, so the warning
// follows the type it ends up with.
TEST(JsonScene, MaterialFieldsTheTypeIgnoresWarn) {
  TempDir dir;
  write_room(dir);
  const Scene s = load_scene(dir.write("scene.json", R"({
    "meshes": [{"file": "room.obj"},
               {"shape": "box", "min": [0, 0, 0], "max": [1, 1, 1], "material": {"diffuse": 0.3, "specular": 0.5}},
               {"shape": "box", "min": [2, 0, 0], "max": [3, 1, 1], "material": {"type": "mirror", "diffuse": 0.2,
                                                                               "exponent": 10}}],
    "materials": {"floor": {"exponent": 20}, "wall": {"exponent": 30}}})"));
  std::vector<std::string> ignored;
  for (const auto& w : s.warnings)
    if (w.find(": ignored by a") != std::string::npos) ignored.push_back(w);
  ASSERT_EQ(ignored.size(), 4u) << ::testing::PrintToString(s.warnings);
  testing::expect_contains(ignored[0], {"scene.json: materials.floor.exponent: ignored by a diffuse material",
                               "\"type\": \"glossy\""});
  testing::expect_contains(ignored[1], {"scene.json: meshes[1].material.specular: ignored by a diffuse material"});
  testing::expect_contains(ignored[2], {"scene.json: meshes[2].material.diffuse: ignored by a mirror material"});
  testing::expect_contains(ignored[3], {"scene.json: meshes[2].material.exponent: ignored by a mirror material"});
  // wall is glossy in its MTL: its exponent is read, not warned about.
  for (const auto& w : ignored) EXPECT_EQ(w.find("wall"), std::string::npos) << w;
}

TEST(JsonScene, TransformsMoveTheVerticesAsComputedByHand) {
  TempDir dir;
  dir.write("tri.obj", "v 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n");
  const Scene s = load_scene(dir.write("t.json", R"({"meshes": [
      {"file": "tri.obj", "transform": {"translate": [10, 20, 30]}},
      {"file": "tri.obj", "transform": {"scale": 2}},
      {"file": "tri.obj", "transform": {"scale": [1, 2, 3]}},
      {"file": "tri.obj", "transform": {"rotate": {"axis": [0, 0, 1], "deg": 90}}},
      {"file": "tri.obj", "transform": {"scale": 2, "rotate": {"axis": [0, 1, 0], "deg": 90}, "translate": [0, 0, 5]}},
      {"file": "tri.obj", "transform": [{"translate": [1, 0, 0]}, {"scale": 3}]},
      {"file": "tri.obj", "transform": {"matrix": [[0, 1, 0, 7], [1, 0, 0, 8], [0, 0, 1, 9], [0, 0, 0, 1]]}},
      {"file": "tri.obj", "transform": {"matrix": [2, 0, 0, 0,  0, 2, 0, 0,  0, 0, 2, 1,  0, 0, 0, 1]}}
    ]})"));
  ASSERT_EQ(s.triangles.size(), 8u);
  auto v0 = [&](size_t t) { return s.triangles[t].v0; };  // image of (1, 0, 0)
  auto v1 = [&](size_t t) { return s.triangles[t].v1; };  // image of (0, 1, 0)
  auto v2 = [&](size_t t) { return s.triangles[t].v2; };  // image of (0, 0, 1)
  expect_near(v0(0), {11, 20, 30});
  expect_near(v0(1), {2, 0, 0});
  expect_near(v1(2), {0, 2, 0});
  expect_near(v2(2), {0, 0, 3});
  expect_near(v0(3), {0, 1, 0});    // x -> y under +90 deg about z
  expect_near(v1(3), {-1, 0, 0});
  expect_near(v0(4), {0, 0, 3});    // scale 2, x -> -z about y, then +5 z
  expect_near(v2(4), {2, 0, 5});
  expect_near(v0(5), {6, 0, 0});    // translate first, then scale
  expect_near(v1(5), {3, 3, 0});
  expect_near(v0(6), {7, 9, 9});
  expect_near(v2(7), {0, 0, 3});
}

// A uniform scale commutes with a rotation; a non-uniform one shows the order: the object's
// own axes are scaled first, then rotated (+90 deg about z: x -> y, y -> -x), then moved.
TEST(JsonScene, NonUniformScaleIsAppliedBeforeTheRotation) {
  TempDir dir;
  dir.write("tri.obj", "v 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n");
  const Scene s = load_scene(dir.write("t.json", R"({"meshes": [{"file": "tri.obj", "transform":
      {"translate": [0, 0, 10], "rotate": {"axis": [0, 0, 1], "deg": 90}, "scale": [1, 2, 3]}}]})"));
  ASSERT_EQ(s.triangles.size(), 1u);
  expect_near(s.triangles[0].v0, {0, 1, 10});   // (1, 0, 0) -> (1, 0, 0) -> (0, 1, 0)
  expect_near(s.triangles[0].v1, {-2, 0, 10});  // (0, 1, 0) -> (0, 2, 0) -> (-2, 0, 0); rotated first: (-1, 0, 0)
  expect_near(s.triangles[0].v2, {0, 0, 13});   // (0, 0, 1) -> (0, 0, 3)
}

// A mirroring transform (negative determinant) would turn faces inside out; corners are
// swapped so that each face's front, and with it a one-sided area light, faces where it did.
TEST(JsonScene, MirroringTransformKeepsEachFaceFront) {
  TempDir dir;
  dir.write("tri.obj", "v -1 0 -1\nv 0 0 1\nv 1 0 -1\nf 1 2 3\n");  // symmetric in x, normal +y
  const Scene s = load_scene(dir.write("m.json", R"({"meshes": [
      {"file": "tri.obj"},
      {"file": "tri.obj", "transform": {"scale": [-1, 1, 1]}},
      {"file": "tri.obj", "transform": {"matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, -1, 0], [0, 0, 0, 1]]}},
      {"file": "tri.obj", "transform": {"scale": [-1, -1, 1]}}
    ],
    "lights": [{"type": "area", "center": [0, 3, 0], "normal": [0, -1, 0], "size": 1, "emission": 10,
                "transform": {"scale": [-1, 1, 1]}}]})"));
  ASSERT_EQ(s.triangles.size(), 6u);
  const Vec3 up = normalize(s.triangles[0].normal());
  expect_near(up, {0, 1, 0});
  expect_near(normalize(s.triangles[1].normal()), up);   // mirrored in x: same front
  expect_near(normalize(s.triangles[2].normal()), up);   // mirrored in z: same front
  expect_near(normalize(s.triangles[3].normal()), -up);  // a rotation by 180 deg about z: turned over
  for (size_t t : {4u, 5u}) expect_near(normalize(s.triangles[t].normal()), {0, -1, 0});  // the light still faces down
}

TEST(JsonScene, CameraLightsAndIdOrder) {
  TempDir dir;
  dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const Scene s = load_scene(dir.write("c.json", R"({
    "comment": "area lights come after all meshes",
    "lights": [
      {"type": "area", "corner": [0, 3, 0], "edge1": [1, 0, 0], "edge2": [0, 0, 1], "emission": [5, 5, 5]},
      {"type": "point", "position": [1, 2, 3], "intensity": [4, 5, 6]}
    ],
    "meshes": [{"file": "tri.obj"}, {"shape": "box", "min": [2, 0, 0], "max": [3, 1, 1]}],
    "camera": {"eye": [0, 1, 5], "look_at": [0, 1, 0], "up": [0, 1, 0], "fov_deg": 45, "lens_radius": 0.1, "focus_distance": 4}
  })"));
  ASSERT_EQ(s.triangles.size(), 1u + 12u + 2u);
  EXPECT_EQ(s.emissive_triangles, (std::vector<uint32_t>{13, 14}));
  expect_near(s.triangles[13].v0, {0, 3, 0}, 0);
  expect_near(s.material_of(13).emission, Vec3(5));
  expect_near(normalize(s.triangles[13].normal()), {0, -1, 0});  // faces down
  ASSERT_EQ(s.point_lights.size(), 1u);
  expect_near(s.point_lights[0].position, {1, 2, 3}, 0);
  expect_near(s.point_lights[0].intensity, {4, 5, 6}, 0);
  expect_near(s.camera.eye, {0, 1, 5}, 0);
  EXPECT_EQ(s.camera.fov_deg, 45.0f);
  EXPECT_EQ(s.camera.lens_radius, 0.1f);
  EXPECT_EQ(s.camera.focus_distance, 4.0f);
  EXPECT_TRUE(s.warnings.empty());
}

// The defaults docs/scene-format.md gives: of a new material and of a glossy one without specular
// or exponent, of a point light's intensity, of an area light's material, and of the camera keys
// left out (focus_distance = |look_at - eye|).
TEST(JsonScene, DocumentedDefaults) {
  TempDir dir;
  dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const Scene s = load_scene(dir.write("d.json", R"({
    "meshes": [{"file": "tri.obj", "material": "new"},
               {"file": "tri.obj", "material": "shiny", "transform": {"translate": [2, 0, 0]}},
               {"file": "tri.obj", "material": "dull", "transform": {"translate": [4, 0, 0]}},
               {"file": "tri.obj", "material": "flat", "transform": {"translate": [6, 0, 0]}}],
    "materials": {"new": {}, "shiny": {"type": "glossy"}, "dull": {"type": "glossy", "diffuse": 0.3},
                  "flat": {"type": "glossy", "exponent": 0}},
    "lights": [{"type": "point", "position": [0, 0, 5]},
               {"type": "area", "corner": [0, 3, 0], "edge1": [1, 0, 0], "edge2": [0, 0, 1], "emission": [5, 4, 3]}],
    "camera": {"eye": [0, 0, 5], "look_at": [0, 3, 1]}
  })"));
  ASSERT_EQ(s.triangles.size(), 6u);
  const Material& fresh = s.material_of(0);
  EXPECT_EQ(fresh.name, "new");
  EXPECT_EQ(fresh.type, Material::Type::Diffuse);
  expect_near(fresh.diffuse, Vec3(0.8f), 0);
  expect_near(fresh.specular, Vec3(0), 0);
  EXPECT_EQ(fresh.exponent, 0.0f);
  expect_near(fresh.emission, Vec3(0), 0);
  // Glossy: specular 0.5, or 1 - the largest diffuse component when that is less; exponent 50
  // unless given.
  const Material& shiny = s.material_of(1);
  EXPECT_EQ(shiny.type, Material::Type::Glossy);
  expect_near(shiny.specular, Vec3(0.2f));
  EXPECT_EQ(shiny.exponent, 50.0f);
  expect_near(s.material_of(2).specular, Vec3(0.5f), 0);
  EXPECT_EQ(s.material_of(2).exponent, 50.0f);
  EXPECT_EQ(s.material_of(3).exponent, 0.0f);
  // A point light without intensity: 1 W/sr. An area light: a black diffuse "lights[i].material".
  ASSERT_EQ(s.point_lights.size(), 1u);
  expect_near(s.point_lights[0].intensity, Vec3(1), 0);
  EXPECT_EQ(s.emissive_triangles, (std::vector<uint32_t>{4, 5}));
  const Material& lamp = s.material_of(4);
  EXPECT_EQ(lamp.name, "lights[1].material");
  EXPECT_EQ(lamp.type, Material::Type::Diffuse);
  expect_near(lamp.diffuse, Vec3(0), 0);
  expect_near(lamp.emission, {5, 4, 3}, 0);
  // Camera keys left out.
  expect_near(s.camera.up, {0, 1, 0}, 0);
  EXPECT_EQ(s.camera.fov_deg, 60.0f);
  EXPECT_EQ(s.camera.lens_radius, 0.0f);
  EXPECT_EQ(s.camera.focus_distance, 5.0f);  // |(0, 3, -4)|
  EXPECT_TRUE(s.warnings.empty());
}

TEST(JsonScene, NoLightsGetsAPointLightAndAWarning) {
  TempDir dir;
  dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const Scene s = load_scene(dir.write("n.json", R"({"meshes": [{"file": "tri.obj"}]})"));
  EXPECT_EQ(s.point_lights.size(), 1u);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("no lights"), std::string::npos);
  expect_near(s.camera.look_at, s.bounds().center());
}

TEST(JsonScene, RepeatedFilesAndScenesDirPrefix) {
  TempDir scenes, dir;
  scenes.write("q.ply",
               "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
               "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n");
  std::string meshes;
  for (int i = 0; i < 5; ++i)
    meshes += std::string(i ? "," : "") + R"({"file": "$RAYSCOUT_SCENES/q.ply", "transform": {"translate": [0, 0, )" +
              std::to_string(i) + "]}}";
  // Restored, not unset, afterwards: the real-scene tests of this process read it.
  const Scene s = [&] {
    const testing::ScopedEnv env("RAYSCOUT_SCENES", scenes.path().string());
    return load_scene(dir.write("r.json", R"({"meshes": [)" + meshes + "]}"));
  }();
  ASSERT_EQ(s.triangles.size(), 10u);
  for (int i = 0; i < 5; ++i) {
    expect_near(s.triangles[2 * i].v0, {0, 0, float(i)}, 0);
    expect_near(s.triangles[2 * i + 1].v2, {0, 1, float(i)}, 0);
  }
}

// A missing "$RAYSCOUT_SCENES/..." file names the variable and where it points: a user with the
// scenes elsewhere learns what to set. A missing file by a plain path does not mention it.
TEST(JsonScene, MissingScenesDirFileNamesTheVariable) {
  TempDir scenes, dir;
  const std::string json = dir.write("r.json", R"({"meshes": [{"file": "$RAYSCOUT_SCENES/q.ply"}]})");
  const std::string missing = "meshes[0].file: " + (scenes.path() / "q.ply").string() +
                              ": cannot open: No such file or directory (\"$RAYSCOUT_SCENES/q.ply\": ";
  const std::string advice = "; set RAYSCOUT_SCENES to the folder that holds the scenes)";
  {
    const testing::ScopedEnv env("RAYSCOUT_SCENES", scenes.path().string());
    const std::string what = testing::input_error_of([&] { load_scene(json); });
    EXPECT_NE(what.find(missing + "RAYSCOUT_SCENES=" + scenes.path().string() + advice), std::string::npos) << what;
  }
  {
    // Unset (an empty value counts as unset): the message names the default that was used.
    const testing::ScopedEnv unset("RAYSCOUT_SCENES", "");
    const testing::ScopedEnv fallback("RAYSCOUT_DEFAULT_SCENES", scenes.path().string());
    const std::string what = testing::input_error_of([&] { load_scene(json); });
    EXPECT_NE(what.find(missing + "RAYSCOUT_SCENES is not set, default " + scenes.path().string() + advice),
              std::string::npos)
        << what;
  }
  const std::string what = testing::input_error_of([&] { load_scene(dir.write("s.json", R"({"meshes": [{"file": "q.ply"}]})")); });
  EXPECT_EQ(what.find("RAYSCOUT_SCENES"), std::string::npos) << what;
}

TEST(JsonScene, ConflictingMaterialNamesKeepTheFirstAndWarn) {
  TempDir dir;
  dir.write("a.mtl", "newmtl paint\nKd 1 0 0\n");
  dir.write("b.mtl", "newmtl paint\nKd 0 0 1\n");
  dir.write("a.obj", "mtllib a.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl paint\nf 1 2 3\n");
  dir.write("b.obj", "mtllib b.mtl\nv 0 0 1\nv 1 0 1\nv 0 1 1\nusemtl paint\nf 1 2 3\n");
  const Scene s = load_scene(dir.write("c.json", R"({"meshes": [{"file": "a.obj"}, {"file": "b.obj"}, {"file": "a.obj"}],
                                                     "lights": [{"type": "point", "position": [0, 0, 3]}]})"));
  ASSERT_EQ(s.triangles.size(), 3u);
  EXPECT_EQ(s.material_ids, (std::vector<uint32_t>{0, 0, 0}));
  expect_near(s.materials[0].diffuse, {1, 0, 0}, 0);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("b.obj: material 'paint' differs from an earlier definition"), std::string::npos)
      << s.warnings[0];
}

TEST(JsonScene, FramingCameraUsesTheGivenFieldOfView) {
  TempDir dir;
  dir.write("tri.obj", "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n");
  const Scene wide = load_scene(dir.write("w.json", R"({"meshes": [{"file": "tri.obj"}], "camera": {"fov_deg": 90}})"));
  const Scene narrow = load_scene(dir.write("n.json", R"({"meshes": [{"file": "tri.obj"}], "camera": {"fov_deg": 30}})"));
  EXPECT_EQ(wide.camera.fov_deg, 90.0f);
  EXPECT_LT(wide.camera.eye.z, narrow.camera.eye.z);  // a narrower view stands further back
  EXPECT_NEAR(wide.camera.eye.z, std::sqrt(2.0f) * std::sqrt(2.0f), 1e-5f);  // radius sqrt(2) / sin(45 deg)
}

TEST(JsonScene, PathsAreRelativeToTheJsonFile) {
  TempDir dir;
  std::filesystem::create_directories(dir.path() / "sub" / "meshes");
  dir.write("sub/meshes/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const Scene s = load_scene(dir.write("sub/s.json", R"({"meshes": [{"file": "meshes/tri.obj"}]})"));
  EXPECT_EQ(s.triangles.size(), 1u);
}

// Mutation checks: each case passed every scene test with a one-line change to the loader and
// fails with it.
TEST(JsonScene, ValuesAtTheEdgesOfWhatTheDocAllows) {
  TempDir dir;
  dir.write("tri.obj", "v 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n");
  const Scene s = load_scene(dir.write("edges.json", R"({
    "meshes": [
      {"file": "tri.obj", "transform": {"rotate": [{"axis": [0, 0, 1], "deg": 90}, {"axis": [1, 0, 0], "deg": 90}]}},
      {"shape": "quad", "center": [0, 0, 0], "normal": [1, 0, 0], "size": [2, 4]},
      {"shape": "box", "min": [0, 0, 0], "max": [1, 1, 1e11]}
    ],
    "lights": [{"type": "area", "emission": [1, 0, 0], "corner": [0, 5, 0], "edge1": [1, 0, 0], "edge2": [0, 0, 1]},
               {"type": "point", "position": [0, 0, -10]}],
    "camera": {"eye": [0, 0, -10], "look_at": [0, 0, 0], "up": [5e-4, 0, 1]}
  })"));
  ASSERT_EQ(s.triangles.size(), 1u + 2u + 12u + 2u);
  // A rotation array applies first to last: x -> y about z, then y -> z about x.
  expect_near(s.triangles[0].v0, {0, 0, 1});
  // A centred quad's height runs along the default up [0, 1, 0].
  Bounds3 quad;
  quad.extend(s.triangles[1].bounds());
  quad.extend(s.triangles[2].bounds());
  expect_near(quad.lo, {0, -2, -1});
  expect_near(quad.hi, {0, 2, 1});
  // A vertex at exactly kMaxCoordinate (1e11) is within it.
  EXPECT_EQ(s.bounds().hi.z, 1e11f);
  // An area light may emit in one channel only.
  EXPECT_EQ(s.emissive_triangles, (std::vector<uint32_t>{15, 16}));
  // An up 5e-4 rad off the view direction still makes a frame (parallel is a sine below 1e-6).
  const CameraFrame f = camera_frame(s.camera, 1.0f);
  EXPECT_NEAR(std::fabs(f.right.y), 1.0f, 1e-6f);
}

// The frame's half extents: tan(fov / 2) high, aspect times that wide.
TEST(JsonScene, CameraFrameHalfWidthIsAspectTimesHalfHeight) {
  Camera c;
  c.eye = {0, 0, 5};
  c.look_at = {0, 0, 0};
  c.up = {0, 1, 0};
  c.fov_deg = 90;
  const CameraFrame f = camera_frame(c, 2.0f);
  EXPECT_NEAR(f.half_h, 1.0f, 1e-6f);
  EXPECT_NEAR(f.half_w, 2.0f, 1e-6f);
}

}  // namespace
}  // namespace rayscout
