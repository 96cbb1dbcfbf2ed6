// Every bad-input case gives an InputError naming the file and line, or the JSON field.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <utility>

#include "rayscout/scene/load_scene.h"
#include "rayscout/scene/mesh.h"
#include "temp_files.h"

namespace rayscout {
namespace {

using testing::expect_contains;
using testing::input_error_of;
using testing::TempDir;

// Loads `text` written as `name` and returns the error message.
std::string error_loading(const TempDir& dir, const std::string& name, const std::string& text) {
  const auto p = dir.write(name, text);
  return input_error_of([&] { load_scene(p); });
}

const std::string kTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

TEST(SceneBadInput, MissingFiles) {
  TempDir dir;
  for (const char* name : {"nope.obj", "nope.ply", "nope.json", "nope.gltf"}) {
    const std::string msg = input_error_of([&] { load_scene(dir.path() / name); });
    expect_contains(msg, {name, "cannot open"});
  }
  expect_contains(input_error_of([&] { load_scene(dir.path()); }), {"is a directory"});
  // A device has no end: /dev/zero used to be read until memory ran out.
  std::filesystem::create_symlink("/dev/zero", dir.path() / "zero.obj");
  expect_contains(input_error_of([&] { load_scene(dir.path() / "zero.obj"); }), {"zero.obj: is a device, not a file"});
  expect_contains(input_error_of([&] { load_scene(dir.write("mesh.stl", "solid")); }), {"mesh.stl", "unknown mesh format"});
  // A scene given where a mesh belongs.
  dir.write("inner.json", R"({"meshes": [{"shape": "box", "min": [0, 0, 0], "max": [1, 1, 1]}]})");
  expect_contains(input_error_of([&] { load_scene(dir.write("outer.json", R"({"meshes": [{"file": "inner.json"}]})")); }),
                  {"inner.json: a .json scene cannot be used as a mesh (meshes are .obj, .ply, .gltf or .glb)"});
}

TEST(SceneBadInput, ObjMalformedLines) {
  TempDir dir;
  expect_contains(error_loading(dir, "a.obj", "# c\nv 0 0 0\nv 1 abc 2\n"), {"a.obj:3: ", "'abc' is not a number"});
  expect_contains(error_loading(dir, "b.obj", "v 0 0\n"), {"b.obj:1: ", "expected 3 numbers, found 2"});
  expect_contains(error_loading(dir, "c.obj", kTriangle + "f 1 2\n"), {"c.obj:4: ", "face with 2 vertices"});
  expect_contains(error_loading(dir, "d.obj", kTriangle + "f 1 x 3\n"), {"d.obj:4: ", "'x' is not an index"});
  expect_contains(error_loading(dir, "e.obj", kTriangle + "f 1/1/1/1 2 3\n"), {"e.obj:4: ", "more than 3 parts"});
  expect_contains(error_loading(dir, "f.obj", kTriangle + "f 0 1 2\n"), {"f.obj:4: ", "index 0 is invalid"});
  expect_contains(error_loading(dir, "g.obj", kTriangle + "usemtl\n"), {"g.obj:4: ", "usemtl without"});
  // Two statements on one line, and more numbers than any vertex extension has.
  expect_contains(error_loading(dir, "h.obj", "v 0 0 0\nv 1 0 0 v 0 1 0\n"),
                  {"h.obj:2: ", "vertex: unexpected 'v' after the 3 coordinates"});
  expect_contains(error_loading(dir, "i.obj", "v 0 0 0 1 2 3 4 5\n"), {"i.obj:1: ", "vertex: 8 numbers"});
  // The vt and vn lines were only counted, so "vt abc" or a vn of one number passed unseen.
  // Not stored, they are checked for form only: exporters write NaN normals of degenerate faces.
  expect_contains(error_loading(dir, "vt.obj", kTriangle + "vt 0.5 abc\nf 1 2 3\n"),
                  {"vt.obj:4: texcoord: 'abc' is not a number"});
  expect_contains(error_loading(dir, "vt4.obj", kTriangle + "vt 0 0 0 0\nf 1 2 3\n"),
                  {"vt4.obj:4: texcoord: expected 1 to 3 numbers (u [v [w]]), found 4"});
  expect_contains(error_loading(dir, "vn.obj", kTriangle + "vn 0 1\nf 1 2 3\n"),
                  {"vn.obj:4: normal: expected 3 numbers (x y z), found 2"});
  expect_contains(error_loading(dir, "vn4.obj", kTriangle + "vn 0 1 0 vn 1 0 0\nf 1 2 3\n"),
                  {"vn4.obj:4: normal: 'vn' is not a number"});
  EXPECT_EQ(load_scene(dir.write("ok.obj", kTriangle + "vt 0.5\nvt 0 1 0\nvn nan -nan inf\nf 1/1/1 2/2/1 3/1/1\n"))
                .triangles.size(),
            1u);
}

TEST(SceneBadInput, ObjIndexOutOfRange) {
  TempDir dir;
  expect_contains(error_loading(dir, "sponza.obj", kTriangle + "f 1 2 3\n\nf 1 2 99999\nf 1 2 3\n"),
                  {"sponza.obj:6: face index 99999 out of range (3 vertices)"});
  expect_contains(error_loading(dir, "neg.obj", kTriangle + "f -1 -2 -4\n"),
                  {"neg.obj:4: ", "face index -4 out of range (3 vertices so far)"});
  expect_contains(error_loading(dir, "vt.obj", kTriangle + "vt 0 0\nf 1/1 2/2 3/1\n"),
                  {"vt.obj:5: ", "texcoord index 2 out of range (1 texcoord)"});
  expect_contains(error_loading(dir, "vn.obj", kTriangle + "vn 0 0 1\nf 1//1 2//1 3//3\n"),
                  {"vn.obj:5: ", "normal index 3 out of range (1 normal)"});
}

// A count of one takes the singular, as "(1 texcoord)" did: "(1 vertices so far)" did not.
TEST(SceneBadInput, IndexErrorsCountOneInTheSingular) {
  TempDir dir;
  expect_contains(error_loading(dir, "v.obj", "v 0 0 0\nf 1 -2 1\n"), {"v.obj:2: face index -2 out of range (1 vertex so far)"});
  expect_contains(error_loading(dir, "vt.obj", kTriangle + "vt 0 0\nf 1/-2 2 3\n"),
                  {"vt.obj:5: texcoord index -2 out of range (1 texcoord so far)"});
  expect_contains(error_loading(dir, "one.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                                                "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                                "end_header\n0 0 0\n3 0 0 1\n"),
                  {"one.ply:11: face index 1 out of range (1 vertex)"});
  std::string bin = "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                    "property float z\nend_header\n";
  bin += std::string(11, '\0');  // one byte short of the vertex
  expect_contains(error_loading(dir, "short.ply", bin), {"short.ply: vertex 0 (byte ", "unexpected end of data (1 vertex declared)"});
}

TEST(SceneBadInput, ObjNonFiniteCoordinates) {
  TempDir dir;
  expect_contains(error_loading(dir, "nan.obj", "v 0 0 0\nv nan 0 0\n"), {"nan.obj:2: ", "nan is not finite"});
  expect_contains(error_loading(dir, "inf.obj", "v 0 0 0\nv 0 -inf 0\n"), {"inf.obj:2: ", "-inf is not finite"});
  expect_contains(error_loading(dir, "big.obj", "v 0 0 1e39\n"), {"big.obj:1: ", "1e39 is out of float range"});
}

TEST(SceneBadInput, EmptyMeshes) {
  TempDir dir;
  expect_contains(error_loading(dir, "empty.obj", ""), {"empty.obj", "no faces"});
  expect_contains(error_loading(dir, "verts.obj", kTriangle), {"verts.obj", "no faces"});
  // Only zero-area faces: nothing is left after dropping them. That is said in the error (it
  // said "no triangles (empty scene)", and the warning counting them was never printed).
  const std::string why = " zero area (repeated indices, collinear vertices, or a transform that flattens them)";
  expect_contains(error_loading(dir, "flat.obj", kTriangle + "f 1 1 2\n"), {"flat.obj: its only triangle has" + why});
  expect_contains(error_loading(dir, "line.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nf 1 2 3 4\nf 4 3 1\n"),
                  {"line.obj: all 3 triangles have" + why});
  dir.write("tri.obj", kTriangle + "f 1 2 3\n");
  expect_contains(error_loading(dir, "tiny.json", R"({"meshes": [{"file": "tri.obj", "transform": {"scale": 1e-30}},
                                                                 {"file": "tri.obj", "transform": {"scale": 1e-25}}]})"),
                  {"tiny.json: meshes[0] (" + (dir.path() / "tri.obj").string() + "): its only triangle has" + why});
  // An entry that lost every triangle beside others that did not was only a warning, so an
  // area light whose quad had parallel edges vanished (and the scene got a point light instead).
  expect_contains(error_loading(dir, "flat_light.json", R"({"meshes": [{"file": "tri.obj"}], "lights": [{"type": "area",
                      "corner": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [2, 0, 0], "emission": 1}]})"),
                  {"flat_light.json: lights[0] (quad): all 2 triangles have" + why});
  expect_contains(error_loading(dir, "flat_mesh.json", R"({"meshes": [{"file": "tri.obj"},
                      {"file": "tri.obj", "transform": {"scale": [1e-30, 1e-30, 1]}}]})"),
                  {"flat_mesh.json: meshes[1] (" + (dir.path() / "tri.obj").string() + "): its only triangle has" + why});
  // No faces at all keeps the plain message.
  expect_contains(error_loading(dir, "none.json", R"({"meshes": []})"), {"none.json: no triangles (empty scene)"});
  expect_contains(error_loading(dir, "empty.ply", "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n"
                                                  "property float y\nproperty float z\nend_header\n"),
                  {"empty.ply", "no faces"});
}

TEST(SceneBadInput, MtlMalformedLine) {
  TempDir dir;
  dir.write("m.mtl", "newmtl a\nKd 0.5 x 0.5\n");
  expect_contains(error_loading(dir, "m.obj", "mtllib m.mtl\n" + kTriangle + "usemtl a\nf 1 2 3\n"),
                  {"m.mtl:2: ", "Kd: 'x' is not a number"});
  dir.write("neg.mtl", "newmtl a\nKd 0.5 0.5 0.5\nKe -5 0 0\n");
  expect_contains(error_loading(dir, "neg.obj", "mtllib neg.mtl\n" + kTriangle + "usemtl a\nf 1 2 3\n"),
                  {"neg.mtl:3: ", "Ke: colour components must be >= 0"});
  dir.write("n.mtl", "Kd 1 1 1\n");
  expect_contains(error_loading(dir, "n.obj", "mtllib n.mtl\n" + kTriangle + "f 1 2 3\n"),
                  {"n.mtl:1: ", "before any newmtl"});
  // Words after the values were ignored, as they are refused after a vertex's.
  const std::pair<const char*, const char*> trailing[] = {
      {"Kd 1 0 0 abc", "Kd: unexpected 'abc' after the colour"},
      {"Ke 0.5 0.5 0.5 v", "Ke: unexpected 'v' after the colour"},
      {"Ks 1 0 0 0.5", "Ks: unexpected '0.5' after the colour"},
      {"Ns 10 junk", "Ns: unexpected 'junk' after the exponent"},
      {"illum 2 xyz", "illum: unexpected 'xyz' after the model number"}};
  for (const auto& [statement, message] : trailing) {
    dir.write("t.mtl", "newmtl a\nKd 0.5\n" + std::string(statement) + " # a comment is fine\n");
    expect_contains(error_loading(dir, "t.obj", "mtllib t.mtl\n" + kTriangle + "usemtl a\nf 1 2 3\n"),
                    {"t.mtl:3: " + std::string(message)});
  }
}

const std::string kPlyHeader =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n";

TEST(SceneBadInput, PlyAsciiErrorsNameTheLine) {
  TempDir dir;
  expect_contains(error_loading(dir, "a.ply", "plx\n"), {"a.ply:1: ", "not a PLY file"});
  expect_contains(error_loading(dir, "b.ply", "ply\nformat ascii 1.0\nelement vertex x\n"), {"b.ply:3: ", "element"});
  expect_contains(error_loading(dir, "c.ply", "ply\nformat utf8 1.0\n"), {"c.ply:2: ", "unknown PLY format"});
  expect_contains(error_loading(dir, "d.ply", kPlyHeader + "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"),
                  {"d.ply:13: ", "face index 7 out of range (3 vertices)"});
  // An int list may hold a negative index; PLY has no relative indices as OBJ has.
  expect_contains(error_loading(dir, "neg.ply", kPlyHeader + "0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n"),
                  {"neg.ply:13: ", "face index -1 out of range (3 vertices)"});
  expect_contains(error_loading(dir, "e.ply", kPlyHeader + "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n"),
                  {"e.ply:11: ", "not finite"});
  expect_contains(error_loading(dir, "f.ply", kPlyHeader + "0 0 0\n1 0\n0 1 0\n3 0 1 2\n"),
                  {"f.ply:11: ", "too few values"});
  expect_contains(error_loading(dir, "g.ply", kPlyHeader + "0 0 0\n1 0 0\n"), {"g.ply:12: ", "unexpected end of file"});
  expect_contains(error_loading(dir, "h.ply", kPlyHeader + "0 0 0\n1 0 0 5\n0 1 0\n3 0 1 2\n"),
                  {"h.ply:11: more values than the header declares for vertex 1 of 3 ('5')"});
  // A vertex count larger than the data read the face line as one more vertex, and the
  // message did not say which vertex of how many.
  std::string count_lie = kPlyHeader;
  count_lie.replace(count_lie.find("vertex 3"), 8, "vertex 10");
  expect_contains(error_loading(dir, "lie.ply", count_lie + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                  {"lie.ply:13: more values than the header declares for vertex 3 of 10 ('2')"});
  expect_contains(error_loading(dir, "few.ply", count_lie + "0 0 0\n1 0 0\n0 1 0\n3 0\n"),
                  {"few.ply:13: too few values for vertex 3 of 10 (property z)"});
  expect_contains(error_loading(dir, "i.ply", kPlyHeader + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2.5\n"),
                  {"i.ply:13: ", "'2.5' is not an integer"});
  expect_contains(error_loading(dir, "j.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n"),
                  {"j.ply:3: ", "lacks x, y or z"});
  expect_contains(error_loading(dir, "k.ply", "ply\nformat ascii 1.0\nelement vertex 1\n"), {"k.ply", "no end_header"});
}

TEST(SceneBadInput, PlyBinaryErrorsNameTheElementAndByte) {
  TempDir dir;
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 2\nproperty list uchar int vertex_indices\nend_header\n";
  std::string body;
  for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) body.append(reinterpret_cast<const char*>(&f), 4);
  auto face = [](int a, int b, int c) {
    std::string s(1, char(3));
    for (int i : {a, b, c}) s.append(reinterpret_cast<const char*>(&i), 4);
    return s;
  };
  const size_t face1_byte = header.size() + body.size() + 13;
  expect_contains(error_loading(dir, "a.ply", header + body + face(0, 1, 2) + face(0, 1, 3)),
                  {"a.ply: face 1 (byte " + std::to_string(face1_byte) + "): face index 3 out of range (3 vertices)"});
  expect_contains(error_loading(dir, "b.ply", header + body + face(0, 1, 2) + face(0, 1, 2).substr(0, 6)),
                  {"b.ply: face 1", "unexpected end of data"});
  std::string nan_body = body;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(nan_body.data() + 4, &nan, 4);
  expect_contains(error_loading(dir, "c.ply", header + nan_body + face(0, 1, 2) + face(0, 1, 2)),
                  {"c.ply: vertex 0 (byte", "vertex coordinate nan is not finite"});
}

// Found by fuzzing: headers whose layout or counts the body loop trusted.
TEST(SceneBadInput, PlyHeaderLayoutAndCounts) {
  TempDir dir;
  // A second vertex element with x y z elsewhere: its layout was applied to the first one
  // (values[3] and [4] of a 3-value row: heap-buffer-overflow).
  expect_contains(error_loading(dir, "twov.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                                 "property float y\nproperty float z\nelement vertex 1\n"
                                                 "property float a\nproperty float b\nproperty float x\n"
                                                 "property float y\nproperty float z\nend_header\n"
                                                 "0 0 0\n1 0 0\n0 1 0\n0 0 0 0 0\n"),
                  {"twov.ply:7: ", "a second vertex element (the first is on line 3)"});
  // Faces before a vertex element that claims more vertices than 32-bit indices address.
  expect_contains(error_loading(dir, "many.ply", "ply\nformat ascii 1.0\nelement face 1\n"
                                                 "property list uchar uint vertex_indices\nelement vertex 4294967297\n"
                                                 "property float x\nproperty float y\nproperty float z\nend_header\n"
                                                 "3 0 1 4294967296\n"),
                  {"many.ply:5: ", "element vertex: 4294967297 vertices, more than 32-bit face indices can address"});
  // A floating-point face index far beyond any integer type.
  expect_contains(error_loading(dir, "fidx.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                                 "property float y\nproperty float z\nelement face 1\n"
                                                 "property list uchar double vertex_indices\nend_header\n"
                                                 "0 0 0\n1 0 0\n0 1 0\n3 0 1 1e30\n"),
                  {"fidx.ply:13: ", "face index 1e+30 out of range (3 vertices)"});
  // These said "face index 1.500000" and "vertex coordinate is not finite" (which one?).
  expect_contains(error_loading(dir, "half.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                                 "property float y\nproperty float z\nelement face 1\n"
                                                 "property list uchar float vertex_indices\nend_header\n"
                                                 "0 0 0\n1 0 0\n0 1 0\n3 0 1.5 2\n"),
                  {"half.ply:13: face index 1.5 is not an integer"});
  expect_contains(error_loading(dir, "inf.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\n"
                                                "property double y\nproperty double z\nelement face 1\n"
                                                "property list uchar int vertex_indices\nend_header\n"
                                                "0 0 0\n1 -inf 0\n0 1 0\n3 0 1 2\n"),
                  {"inf.ply:11: vertex coordinate -inf is not finite"});
  // A binary element without properties takes no bytes: a huge count must not loop forever.
  std::string bin = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                    "property float z\nelement nothing 1000000000000000\nelement face 1\n"
                    "property list uchar int vertex_indices\nend_header\n";
  for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) bin.append(reinterpret_cast<const char*>(&f), 4);
  bin += char(3);
  for (int i : {0, 1, 3}) bin.append(reinterpret_cast<const char*>(&i), 4);
  expect_contains(error_loading(dir, "empty_el.ply", bin), {"empty_el.ply: face 0 (byte", "face index 3 out of range"});
}

// A property declared twice, integers beyond their type, data after the last element and
// format versions other than 1.0 were accepted.
TEST(SceneBadInput, PlyPropertyDeclaredTwice) {
  TempDir dir;
  expect_contains(error_loading(dir, "dup.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                                "property float y\nproperty float z\nproperty float x\nend_header\n"),
                  {"dup.ply:7: a second property x in element vertex (the first is on line 4)"});
}

TEST(SceneBadInput, PlyAsciiIntegerBeyondItsType) {
  TempDir dir;
  expect_contains(error_loading(dir, "uchar.ply", kPlyHeader + "0 0 0\n1 0 0\n0 1 0\n300 0 1 2\n"),
                  {"uchar.ply:13: '300' is out of range for uchar (0 to 255)"});
  const std::string flags =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "property uint flags\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  expect_contains(error_loading(dir, "uint.ply", flags + "0 0 0 0\n1 0 0 -1\n0 1 0 0\n3 0 1 2\n"),
                  {"uint.ply:12: '-1' is out of range for uint (0 to 4294967295)"});
  expect_contains(error_loading(dir, "int.ply", kPlyHeader + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2147483648\n"),
                  {"int.ply:13: '2147483648' is out of range for int (-2147483648 to 2147483647)"});
  // The limits themselves are fine.
  const Scene s = load_scene(dir.write("ok.ply", flags + "0 0 0 4294967295\n1 0 0 0\n0 1 0 0\n3 0 1 2\n"));
  EXPECT_EQ(s.triangles.size(), 1u);
}

TEST(SceneBadInput, PlyDataAfterTheLastElement) {
  TempDir dir;
  const std::string body = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  expect_contains(error_loading(dir, "extra.ply", kPlyHeader + body + "\n3 0 1 2\n"),
                  {"extra.ply:15: data after the last element ('3')"});
  // Blank lines and spaces at the end are fine.
  EXPECT_EQ(load_scene(dir.write("blank.ply", kPlyHeader + body + "\n  \n\t\n")).triangles.size(), 1u);
  // Binary: bytes after the last element are ignored, as rply and most readers do.
  std::string bin = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) bin.append(reinterpret_cast<const char*>(&f), 4);
  bin += char(3);
  for (int i : {0, 1, 2}) bin.append(reinterpret_cast<const char*>(&i), 4);
  const Scene s = load_scene(dir.write("tail.ply", bin + std::string("\n\0\0\0", 4)));
  ASSERT_EQ(s.triangles.size(), 1u);
  EXPECT_EQ(s.triangles[0].v1.x, 1.0f);
}

TEST(SceneBadInput, PlyFormatVersion) {
  TempDir dir;
  const std::string rest = kPlyHeader.substr(kPlyHeader.find("element")) + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  expect_contains(error_loading(dir, "v2.ply", "ply\nformat ascii 2.0\n" + rest),
                  {"v2.ply:2: unsupported PLY version '2.0' (1.0 is the only one)"});
  expect_contains(error_loading(dir, "none.ply", "ply\nformat ascii\n" + rest),
                  {"none.ply:2: format line without a version (expected 'format ascii 1.0')"});
  EXPECT_EQ(load_scene(dir.write("v1.ply", "ply\nformat ascii 1.0\n" + rest)).triangles.size(), 1u);
}

// Words after a header statement were ignored ("property float z junk", "element face 1 2",
// "end_header x"), and a second format line silently replaced the first, so ascii data was read
// as binary ("unexpected end of data"). As in OBJ and MTL, they are errors.
TEST(SceneBadInput, PlyHeaderStatementsEndWithTheirValues) {
  TempDir dir;
  const std::string vertex = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
  const std::string face = "element face 1\nproperty list uchar int vertex_indices\n";
  const std::string body = "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const std::pair<std::string, std::string> cases[] = {
      {"ply\nformat ascii 1.0 x\n" + vertex + face + body, "h.ply:2: format: unexpected 'x' after the version"},
      {"ply\nformat ascii 1.0\nelement vertex 3 7\nproperty float x\nproperty float y\nproperty float z\n" + face + body,
       "h.ply:3: element: unexpected '7' after the count"},
      {"ply\nformat ascii 1.0\n" + vertex.substr(0, vertex.size() - 1) + " junk\n" + face + body,
       "h.ply:6: property: unexpected 'junk' after the name"},
      {"ply\nformat ascii 1.0\n" + vertex + "element face 1\nproperty list uchar int vertex_indices 4\n" + body,
       "h.ply:8: property: unexpected '4' after the name"},
      {"ply\nformat ascii 1.0\n" + vertex + face + "end_header x\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
       "h.ply:9: end_header: unexpected 'x' after it"},
      {"ply\nformat ascii 1.0\nformat binary_little_endian 1.0\n" + vertex + face + body,
       "h.ply:3: a second format line (the first is on line 2)"},
  };
  for (const auto& [text, message] : cases) expect_contains(error_loading(dir, "h.ply", text), {message});
  // White space and comments are fine.
  EXPECT_EQ(load_scene(dir.write("ok.ply", "ply\nformat ascii 1.0 \ncomment a b c\n" + vertex + face + "end_header\t\n"
                                           "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")).triangles.size(), 1u);
}

// A NUL in a quoted token ended the message there (what() is a C string).
TEST(SceneBadInput, ControlBytesInQuotedInputAreEscaped) {
  TempDir dir;
  expect_contains(error_loading(dir, "nul.obj", std::string("v 0 0 0\nv 1 a\0b 0\n", 18)),
                  {"nul.obj:2: vertex: 'a\\x00b' is not a number"});
  expect_contains(error_loading(dir, "esc.obj", kTriangle + "f 1 2 \x1b[2J\n"),
                  {"esc.obj:4: face vertex '\\x1b[2J' is not an index"});
  expect_contains(error_loading(dir, "nul.json", R"({"meshes": [{"shape": "box", "min": [0, 0, 0], "max": [1, 1, 1], "a\u0000b": 1}]})"),
                  {"nul.json: meshes[0].a\\x00b: unknown key"});
}

// Warnings quoted names raw, so an OBJ's "usemtl <ESC>[2J" cleared the terminal that
// `rayscout info` printed it to. Warnings escape control bytes as errors do.
TEST(SceneBadInput, ControlBytesInWarningsAreEscaped) {
  TempDir dir;
  dir.write("esc.mtl", "newmtl bright\x1b[2J\nKd 1 1 1\nKs 1 1 1\n");
  const Scene obj = load_scene(dir.write("esc.obj", "mtllib esc.mtl\nmtllib gone\x1b.mtl\n" + kTriangle +
                                                       "usemtl bright\x1b[2J\nf 1 2 3\nusemtl nope\x07\nf 1 2 3\n"));
  dir.write("dim.mtl", "newmtl bright\x1b[2J\nKd 0.1 0.1 0.1\n");
  dir.write("dim.obj", "mtllib dim.mtl\n" + kTriangle + "usemtl bright\x1b[2J\nf 1 2 3\n");
  const Scene json = load_scene(dir.write("esc.json", R"({"meshes": [{"file": "esc.obj"}, {"file": "dim.obj"}],
                                                          "materials": {"unused\u001b": {"diffuse": 0.5}}})"));
  std::vector<std::string> warnings = obj.warnings;
  warnings.insert(warnings.end(), json.warnings.begin(), json.warnings.end());
  ASSERT_GE(warnings.size(), 6u);
  for (const std::string& w : warnings)
    for (const char c : w) EXPECT_FALSE(static_cast<unsigned char>(c) < 0x20 || c == 0x7f) << "control byte in: " << w;
  expect_contains(obj.warnings[0], {"esc.mtl:1: material 'bright\\x1b[2J': Kd + Ks reaches 2"});
  expect_contains(obj.warnings[1], {"esc.obj:2: material library 'gone\\x1b.mtl' not found"});
  expect_contains(obj.warnings[2], {"esc.obj:8: 1 material ('nope\\x07') not defined"});
  std::string all;
  for (const std::string& w : json.warnings) all += w + "\n";
  expect_contains(all, {"dim.obj: material 'bright\\x1b[2J' differs from an earlier definition",
                        "esc.json: materials.unused\\x1b: no triangle uses this material"});
}

// The OS reads a path up to its first NUL, so "ok.obj\u0000junk.obj" loaded ok.obj (and
// "mtllib red.mtl<NUL>junk" read red.mtl); messages quoting a path were cut at a NUL, and
// printed other control bytes raw.
TEST(SceneBadInput, NulInAFileNameIsAnErrorAndPathsInMessagesAreEscaped) {
  TempDir dir;
  dir.write("ok.obj", kTriangle + "f 1 2 3\n");
  dir.write("red.mtl", "newmtl red\nKd 1 0 0\n");
  expect_contains(error_loading(dir, "nul.json", R"({"meshes": [{"file": "ok.obj\u0000junk.obj"}]})"),
                  {"nul.json: meshes[0].file: file name \"ok.obj\\x00junk.obj\" holds a NUL character (\\u0000), "
                   "which no file name can contain"});
  expect_contains(error_loading(dir, "light.json", R"({"meshes": [{"file": "ok.obj"}], )"
                                                   R"("lights": [{"type": "area", "emission": 1, "file": "nope\u0000.obj"}]})"),
                  {"light.json: lights[0].file: file name \"nope\\x00.obj\" holds a NUL character"});
  expect_contains(error_loading(dir, "nul.obj", std::string("mtllib red.mtl\0junk\n", 20) + kTriangle + "f 1 2 3\n"),
                  {"nul.obj:1: mtllib 'red.mtl\\x00junk': a NUL byte in the file name, which no file name can contain"});
  expect_contains(input_error_of([&] { load_scene(dir.path() / "no\x1bpe.obj"); }), {"no\\x1bpe.obj: cannot open: "});
  expect_contains(input_error_of([&] { load_scene(dir.path() / "mesh\x1b.stl"); }),
                  {"mesh\\x1b.stl: unknown mesh format '.stl'"});
  expect_contains(error_loading(dir, "esc.json", R"({"meshes": [{"file": "no\u001bpe.obj"}]})"),
                  {"esc.json: meshes[0].file: ", "no\\x1bpe.obj: cannot open: "});
}

// Found by fuzzing.
TEST(SceneBadInput, ObjSmallestIndexAndDirectoryMtllib) {
  TempDir dir;
  expect_contains(error_loading(dir, "min.obj", kTriangle + "f -9223372036854775808 1 2\n"),
                  {"min.obj:4: ", "face index -9223372036854775808 out of range (3 vertices so far)"});
  std::filesystem::create_directory(dir.path() / "lib");
  expect_contains(error_loading(dir, "dir.obj", "mtllib lib\n" + kTriangle + "f 1 2 3\n"),
                  {"dir.obj:1: ", "material library 'lib' is a directory, not a file"});
  // "/dev/zero: is a device, not a file" did not name the OBJ that referenced it.
  expect_contains(error_loading(dir, "dev.obj", kTriangle + "mtllib /dev/zero\nf 1 2 3\n"),
                  {"dev.obj:4: material library '/dev/zero' is a device, not a file"});
}

// Random bytes given as an OBJ were read as a few unknown statements and gave "no faces
// (empty mesh)". A line the reader would ignore that holds a byte no text has is an error.
TEST(SceneBadInput, BinaryDataIsNotReadAsObjOrMtl) {
  TempDir dir;
  const char png[] = "\x89PNG\r\n\x1a\n\0\0\0\rIHDR\0\0\0\x10";  // a PNG's first bytes
  expect_contains(error_loading(dir, "png.obj", std::string(png, sizeof png - 1)),
                  {"png.obj:2: not an OBJ text file (binary data)"});
  std::string noise;
  for (uint32_t x = 12345; noise.size() < 4096;) noise += char((x = x * 1664525u + 1013904223u) >> 24);
  expect_contains(error_loading(dir, "noise.obj", noise), {"noise.obj:1: not an OBJ text file (binary data)"});
  // A damaged file: a block of NULs after valid lines.
  expect_contains(error_loading(dir, "nuls.obj", kTriangle + "f 1 2 3\n" + std::string(512, '\0') + "\nf 1 2 3\n"),
                  {"nuls.obj:5: binary data where an OBJ statement belongs (a damaged file?)"});
  dir.write("bin.mtl", noise);
  expect_contains(error_loading(dir, "bin.obj", "mtllib bin.mtl\n" + kTriangle + "f 1 2 3\n"),
                  {"bin.mtl:1: not an MTL text file (binary data)"});
  // Text is fine: UTF-8 names, tabs, CR LF, form feeds, and statements rayscout ignores.
  dir.write("ok.mtl", "newmtl caf\xc3\xa9\r\n\tKd 0.5\r\nmap_Kd t\xc3\xa9.png\r\n");
  const Scene s = load_scene(dir.write("text.obj", "mtllib ok.mtl\r\ng \xe6\x9c\xba\xe6\xa2\xb0\r\no part\f\r\ns 1\r\n" + kTriangle +
                                                   "usemtl caf\xc3\xa9\r\nf 1 2 3\r\nl 1 2\r\n"));
  ASSERT_EQ(s.triangles.size(), 1u);
  EXPECT_TRUE(s.warnings.empty()) << s.warnings[0];
}

// A JSON scene next to a valid mesh, so errors come from the JSON itself.
std::string json_error(const TempDir& dir, const std::string& json) {
  dir.write("tri.obj", kTriangle + "f 1 2 3\n");
  return error_loading(dir, "scene.json", json);
}

// These said "unknown mesh format ''", and an empty "file" gave "meshes[0].file: : unknown ...".
TEST(SceneBadInput, NoExtensionAndEmptyFileName) {
  TempDir dir;
  expect_contains(error_loading(dir, "mesh", kTriangle + "f 1 2 3\n"),
                  {"mesh: no file extension to tell the format by (expected .obj, .ply, .gltf, .glb or a .json scene)"});
  expect_contains(json_error(dir, R"({"meshes": [{"file": ""}]})"), {"scene.json: meshes[0].file: empty file name"});
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj"}], "lights": [{"type": "area", "emission": 1, "file": ""}]})"),
                  {"scene.json: lights[0].file: empty file name"});
  // A folder is said to be one, whatever its name ends in.
  std::filesystem::create_directory(dir.path() / "meshes");
  expect_contains(json_error(dir, R"({"meshes": [{"file": "meshes/"}]})"),
                  {"scene.json: meshes[0].file: ", "meshes/: is a directory, not a file"});
}

TEST(SceneBadInput, JsonSyntaxAndTypes) {
  TempDir dir;
  expect_contains(json_error(dir, "{\n  \"meshes\": [\n    {\"file\": \"tri.obj\",}\n  ]\n}\n"),
                  {"scene.json: invalid JSON", "line 3"});
  expect_contains(json_error(dir, "[1, 2]"), {"scene.json: (root): expected an object"});
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj"}], "camera": {"fov_deg": "wide"}})"),
                  {"scene.json: camera.fov_deg: expected a number"});
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj"}], "camera": {"eye": [0, 1]}})"),
                  {"scene.json: camera.eye: expected an array of 3 numbers"});
  expect_contains(json_error(dir, R"({"meshes": {"file": "tri.obj"}})"), {"scene.json: meshes: expected an array"});
  expect_contains(json_error(dir, R"({"meshes": [{"file": 3}]})"), {"scene.json: meshes[0].file: expected a string"});
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj", "transform": {"rotate": {"axis": [0,1,0], "deg": true}}}]})"),
                  {"scene.json: meshes[0].transform.rotate.deg: expected a number"});
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj"}], "lights": [{"type": "point", "position": [0,1,0], "intensity": [1,-1,1]}]})"),
                  {"scene.json: lights[0].intensity: colour components must be >= 0"});
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj"}], "camera": {"fov_deg": 200}})"),
                  {"scene.json: camera.fov_deg: expected a number in (0, 180)"});
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj"}], "camera": {"eye": [0,0,1], "look_at": [0,0,0], "up": [0,0,2]}})"),
                  {"scene.json: camera.up: is parallel"});
  // eye == look_at said "camera.focus_distance: |look_at - eye| rounds to 0 in float; give a
  // focus_distance", and a focus_distance given then gave this error.
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj"}], "camera": {"eye": [0.3,0.3,0], "look_at": [0.3,0.3,0]}})"),
                  {"scene.json: camera.look_at: must differ from camera.eye"});
  // A key left out holds its default, which the message names: these named only keys the file
  // does not give. (tri.obj spans [0, 1] x [0, 1] x {0}: its centre is (0.5, 0.5, 0).)
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj"}], "camera": {"eye": [0.5, 3, 0]}})"),
                  {"scene.json: camera.up: is parallel to the view direction (camera.up is not given and defaults to "
                   "[0, 1, 0]"});
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj"}], "camera": {"eye": [0.5, 0.5, 0]}})"),
                  {"scene.json: camera.look_at: must differ from camera.eye (camera.look_at is not given and defaults "
                   "to the centre of the bounds, (0.5, 0.5, 0)"});
  // Given keys are the user's own: no default to name.
  for (const char* camera : {R"({"eye": [0,0,1], "look_at": [0,0,0], "up": [0,0,2]})",
                             R"({"eye": [0.3,0.3,0], "look_at": [0.3,0.3,0]})"})
    EXPECT_EQ(json_error(dir, std::string(R"({"meshes": [{"file": "tri.obj"}], "camera": )") + camera + "}")
                  .find("is not given"),
              std::string::npos)
        << camera;
}

TEST(SceneBadInput, JsonUnknownKeysAndValues) {
  TempDir dir;
  expect_contains(json_error(dir, R"({"mesh": []})"), {"scene.json: mesh: unknown key"});
  // nlohmann keeps the last of two equal keys: a typo would pass silently.
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj"}], "camera": {"fov_deg": 30, "fov_deg": 90}})"),
                  {"scene.json: key \"fov_deg\" appears twice in one object"});
  // The same key in two objects is fine.
  dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_NO_THROW(load_scene(dir.write("two.json", R"({"meshes": [{"file": "tri.obj"}, {"file": "tri.obj"}]})")));
  // Found by fuzzing: nlohmann reports this as out_of_range, not as a parse_error.
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj"}], "camera": {"fov_deg": 1e400}})"),
                  {"scene.json: invalid JSON: number overflow parsing '1e400'"});
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj"}], "camera": {"fvo_deg": 40}})"),
                  {"scene.json: camera.fvo_deg: unknown key", "fov_deg"});
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj", "transfrom": {}}]})"),
                  {"scene.json: meshes[0].transfrom: unknown key"});
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj"}], "materials": {"m": {"typ": "mirror"}}})"),
                  {"scene.json: materials.m.typ: unknown key"});
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj"}], "materials": {"m": {"type": "metal"}}})"),
                  {"scene.json: materials.m.type: expected \"diffuse\", \"mirror\" or \"glossy\""});
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj", "material": "nosuch"}]})"),
                  {"scene.json: meshes[0].material: unknown material \"nosuch\""});
  expect_contains(json_error(dir, R"({"meshes": [{"shape": "sphere"}]})"), {"scene.json: meshes[0].shape: expected \"quad\" or \"box\""});
  expect_contains(json_error(dir, R"({"meshes": [{"shape": "quad", "corner": [0,0,0], "edge1": [1,0,0]}]})"),
                  {"scene.json: meshes[0].edge2: missing"});
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj", "shape": "box"}]})"),
                  {"scene.json: meshes[0]: needs exactly one of"});
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj"}], "lights": [{"type": "spot"}]})"),
                  {"scene.json: lights[0].type: expected \"point\" or \"area\""});
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj", "transform": {"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,1,1]}}]})"),
                  {"scene.json: meshes[0].transform.matrix: last row must be 0 0 0 1"});
  expect_contains(json_error(dir, R"({"meshes": []})"), {"scene.json: no triangles"});
  // Dark lights: the image would be black without a word.
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj"}], "lights": [{"type": "point", "position": [0,0,1], "intensity": [0,0,0]}]})"),
                  {"scene.json: lights[0].intensity: a point light must emit (> 0)"});
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj"}], "lights": [{"type": "area", "emission": 0, "shape": "quad", "corner": [0,0,1], "edge1": [1,0,0], "edge2": [0,1,0]}]})"),
                  {"scene.json: lights[0].emission: an area light must emit (> 0)"});
  // An empty key was named by its object alone ("(root): unknown key", "meshes[0].: unknown key").
  expect_contains(json_error(dir, R"({"": 1, "meshes": [{"file": "tri.obj"}]})"),
                  {"scene.json: (root): unknown empty key \"\" (expected one of: meshes, camera, lights, materials)"});
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj", "": 1}]})"),
                  {"scene.json: meshes[0]: unknown empty key \"\" (expected one of: file, material, transform)"});
  // Two inline materials of one name: the second is refused, whatever the order of definition.
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj", "material": {"name": "x"}},
                                                  {"file": "tri.obj", "material": {"name": "x", "diffuse": 0.1}}]})"),
                  {"scene.json: meshes[1].material.name: material \"x\" is already defined"});
  // An empty material name was taken (an MTL's newmtl needs one), listed as "materials.".
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj"}], "materials": {"": {"diffuse": 0.5}}})"),
                  {"scene.json: materials: a material name must not be empty"});
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj", "material": {"name": ""}}]})"),
                  {"scene.json: meshes[0].material.name: a material name must not be empty"});
}

// Values docs/scene-format.md refuses (shapes, transforms) and its example messages, word for word.
TEST(SceneBadInput, JsonShapeAndTransformValuesTheDocRefuses) {
  TempDir dir;
  const auto msg = [&](const std::string& json) {  // from the file name on (the folder varies)
    const std::string m = json_error(dir, json);
    return m.substr(std::min(m.size(), m.find("scene.json")));
  };
  EXPECT_EQ(msg(R"({"meshes": [{"file": "tri.obj"}], "camera": {"fov_deg": "wide"}})"),
            "scene.json: camera.fov_deg: expected a number, found string");
  EXPECT_EQ(msg(R"({"meshes": [{"file": "tri.obj"}], "camera": {"fvo_deg": 60}})"),
            "scene.json: camera.fvo_deg: unknown key (expected one of: eye, look_at, up, fov_deg, lens_radius, "
            "focus_distance)");
  EXPECT_EQ(msg(R"({"meshes": []})"), "scene.json: no triangles (empty scene)");
  // A zero scale, on any axis, flattens the mesh like a singular matrix.
  for (const char* scale : {"0", "[1, 0, 1]"})
    EXPECT_EQ(msg(std::string(R"({"meshes": [{"file": "tri.obj", "transform": {"scale": )") + scale + "}}]}"),
              "scene.json: meshes[0].transform.scale: scale must not be zero (it flattens the mesh)");
  EXPECT_EQ(msg(R"({"meshes": [{"file": "tri.obj", "transform": {"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1],
                                                                            "translate": [1, 0, 0]}}]})"),
            "scene.json: meshes[0].transform: \"matrix\" cannot be combined with translate/scale/rotate");
  EXPECT_EQ(msg(R"({"meshes": [{"file": "tri.obj", "transform": {"rotate": {"axis": [0, 0, 0], "deg": 90}}}]})"),
            "scene.json: meshes[0].transform.rotate.axis: direction must not be zero");
  // A box needs max above min on every axis; a quad's size must be positive.
  EXPECT_EQ(msg(R"({"meshes": [{"shape": "box", "min": [0, 0, 0], "max": [1, 0, 1]}]})"),
            "scene.json: meshes[0].max: must exceed min on every axis");
  EXPECT_EQ(msg(R"({"meshes": [{"shape": "quad", "center": [0, 0, 0], "normal": [0, 0, 1], "size": 0}]})"),
            "scene.json: meshes[0].size: expected a positive number");
  EXPECT_EQ(msg(R"({"meshes": [{"shape": "quad", "center": [0, 0, 0], "normal": [0, 0, 1], "size": [1, -2]}]})"),
            "scene.json: meshes[0].size[1]: expected a positive number");
  EXPECT_EQ(msg(R"({"meshes": [{"shape": "quad", "center": [0, 0, 0], "normal": [0, 0, 1], "size": [1]}]})"),
            "scene.json: meshes[0].size: expected a number or [width, height]");
  EXPECT_EQ(msg(R"({"meshes": [{"file": "tri.obj"}], "lights": [{"type": "area", "emission": 1, "file": "tri.obj",
                                                                         "shape": "box"}]})"),
            "scene.json: lights[0]: needs \"file\" or a shape, not both");
}

// An unknown material name said only "define it under materials", even when "materials" held
// the name it misspelt: it names the likely one, else the defined ones.
TEST(SceneBadInput, JsonUnknownMaterialNamesWhatIsDefined) {
  TempDir dir;
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj"}, {"shape": "box", "min": [0, 0, 0], "max": [1, 1, 1],
                                      "material": "flor"}], "materials": {"floor": {"diffuse": 0.5}}})"),
                  {"scene.json: meshes[1].material: unknown material \"flor\" (did you mean \"floor\"?)"});
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj", "material": "Floor "}],
                                      "materials": {"floor": {"diffuse": 0.5}}})"),
                  {"did you mean \"floor\"?"});
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj", "material": "stone"}],
                                      "materials": {"floor": {"diffuse": 0.5}}})"),
                  {"unknown material \"stone\" (defined: \"floor\"; define it under \"materials\")"});
  expect_contains(json_error(dir, R"({"meshes": [{"shape": "box", "min": [0, 0, 0], "max": [1, 1, 1], "material": "m"}]})"),
                  {"unknown material \"m\" (no material is defined: define it under \"materials\")"});
}

// Keys of the other form of a shape were ignored.
TEST(SceneBadInput, JsonShapeKeysOfAnotherForm) {
  TempDir dir;
  expect_contains(json_error(dir, R"({"meshes": [{"shape": "quad", "corner": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0], "up": [0, 0, 1]}]})"),
                  {"scene.json: meshes[0].up: does not belong to a quad given by corner, edge1 and edge2"});
  expect_contains(json_error(dir, R"({"meshes": [{"shape": "quad", "center": [0, 0, 0], "normal": [0, 0, 1], "size": 1, "max": [1, 1, 1]}]})"),
                  {"scene.json: meshes[0].max: does not belong to a quad given by center, normal and size"});
  expect_contains(json_error(dir, R"({"meshes": [{"shape": "box", "min": [0, 0, 0], "max": [1, 1, 1], "size": 2}]})"),
                  {"scene.json: meshes[0].size: does not belong to a box (given by min and max)"});
  expect_contains(json_error(dir, R"({"meshes": [{"shape": "box", "min": [0, 0, 0], "max": [1, 1, 1], "corner": [0, 0, 0]}]})"),
                  {"scene.json: meshes[0].corner: does not belong to a box (given by min and max)"});
  const std::string tri = R"({"meshes": [{"file": "tri.obj"}], "lights": [{"type": "area", "emission": 1, )";
  expect_contains(json_error(dir, tri + R"("center": [0, 0, 0], "normal": [0, 0, 1], "size": 1, "min": [0, 1, 0]}]})"),
                  {"scene.json: lights[0].min: does not belong to a quad given by center, normal and size"});
  expect_contains(json_error(dir, tri + R"("file": "tri.obj", "size": 1}]})"),
                  {"scene.json: lights[0].size: does not belong to an area light given by a file"});
}

// A singular matrix gave "no triangles (empty scene)", unlike "scale": 0.
TEST(SceneBadInput, JsonSingularMatrix) {
  TempDir dir;
  for (const char* m : {"[0,0,0,0, 0,0,0,0, 0,0,0,0, 0,0,0,1]", "[[1,0,0,5], [0,1,0,0], [1,1,0,0], [0,0,0,1]]"})
    expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj", "transform": {"matrix": )" + std::string(m) + "}}]}"),
                    {"scene.json: meshes[0].transform.matrix: matrix must not be singular (determinant 0 flattens the mesh)"});
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj", "transform": [{"translate": [1, 0, 0]}, {"matrix": [0,0,0,0, 0,0,0,0, 0,0,0,0, 0,0,0,1]}]}]})"),
                  {"scene.json: meshes[0].transform[1].matrix: matrix must not be singular"});
}

// docs/scene-format.md: reflectances in [0, 1], and a glossy material's diffuse + specular
// <= 1 per channel; the error names the file, the field and the value.
TEST(SceneBadInput, JsonMaterialsReflectingMoreThanArrives) {
  TempDir dir;
  dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  auto with = [](const std::string& material) {
    return R"({"meshes": [{"file": "tri.obj", "material": "m"}], "materials": {"m": )" + material + "}}";
  };
  expect_contains(json_error(dir, with(R"({"diffuse": 2.0})")),
                  {"scene.json: materials.m.diffuse: 2 is above 1: a reflectance must be in [0, 1]"});
  expect_contains(json_error(dir, with(R"({"type": "mirror", "specular": [0.5, 1.5, 0]})")),
                  {"scene.json: materials.m.specular: 1.5 is above 1"});
  expect_contains(json_error(dir, with(R"({"type": "glossy", "diffuse": [0.486, 0.631, 0.663], "specular": 0.9})")),
                  {"scene.json: materials.m: diffuse + specular is 1.563 in channel 2",
                   "(diffuse [0.486, 0.631, 0.663], specular [0.9, 0.9, 0.9])", "<= 1 in every channel"});
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj", "material": {"diffuse": [0, 0, 1.01]}}]})"),
                  {"scene.json: meshes[0].material.diffuse: 1.01 is above 1"});
  // At the limits, and a glossy default (specular 0.5) that fits beside the default diffuse 0.8.
  EXPECT_NO_THROW(load_scene(dir.write("ok.json", with(R"({"type": "glossy", "diffuse": 0.4, "specular": 0.6})"))));
  const Scene s = load_scene(dir.write("def.json", with(R"({"type": "glossy"})")));
  EXPECT_NEAR(s.material_of(0).specular.x, 0.2f, 1e-6f);
  EXPECT_NEAR(s.material_of(0).diffuse.x, 0.8f, 1e-6f);
}

// Found by fuzzing: ordered_json copies values recursively (while parsing too, when an object
// grows), so a deeply nested value overflowed the stack.
TEST(SceneBadInput, JsonDeepNesting) {
  TempDir dir;
  const std::string deep = std::string(200000, '[') + std::string(200000, ']');
  expect_contains(json_error(dir, "{\"comment\": " + deep + R"(, "meshes": [{"file": "tri.obj"}]})"),
                  {"scene.json: JSON nested deeper than 256 arrays and objects at line 1, column 268"});
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj", "material": {"diffuse": )" + deep + "}}]}"),
                  {"scene.json: JSON nested deeper than 256 arrays and objects at line 1, column "});
  // 256 levels are fine, and brackets inside strings do not count.
  const std::string ok = std::string(255, '[') + "\"[[{\\\"\"" + std::string(255, ']');
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj"}], "comment": )" + ok + R"(, "camera": 1})"),
                  {"scene.json: camera: expected an object, found number"});
}

// Found by fuzzing: shapes and cameras whose numbers are finite but whose sums are not.
TEST(SceneBadInput, JsonShapeAndCameraOverflow) {
  TempDir dir;
  expect_contains(json_error(dir, R"({"meshes": [{"shape": "box", "min": [-3e38, -3e38, -3e38], "max": [3e38, 3e38, 3e38]}]})"),
                  {"scene.json: meshes[0] (shape box): vertex 0 at (-3e+38, -3e+38, -3e+38) is beyond +-1e11"});
  // Finite but huge: the triangle test's products (wrong hits) and the renderer's squared distances
  // (a black image) would overflow.
  expect_contains(json_error(dir, R"({"meshes": [{"shape": "box", "min": [0, 0, 0], "max": [1, 1, 1], "transform": {"scale": 1e20}}]})"),
                  {"scene.json: meshes[0] (shape box): vertex 1 (transformed) at (0, 0, 1e+20) is beyond +-1e11"});
  expect_contains(json_error(dir, R"({"meshes": [{"shape": "box", "min": [0, 0, 0], "max": [1, 1, 2e11]}]})"),
                  {"scene.json: meshes[0] (shape box): vertex 1 at (0, 0, 2e+11) is beyond +-1e11"});
  // Camera and light positions and the lens lengths are squared like vertices.
  const std::string tri = R"({"meshes": [{"file": "tri.obj"}], )";
  expect_contains(json_error(dir, tri + R"("camera": {"eye": [-1e20, 0, 0], "look_at": [1e20, 0, 0]}})"),
                  {"scene.json: camera.eye: is beyond +-1e11"});
  expect_contains(json_error(dir, tri + R"("camera": {"look_at": [0, 0, -2e18]}})"), {"scene.json: camera.look_at: is beyond"});
  expect_contains(json_error(dir, tri + R"("camera": {"lens_radius": 0.1, "focus_distance": 2e19}})"),
                  {"scene.json: camera.focus_distance: is beyond +-1e11"});
  expect_contains(json_error(dir, tri + R"("camera": {"lens_radius": 1e19}})"), {"scene.json: camera.lens_radius: is beyond"});
  expect_contains(json_error(dir, tri + R"("lights": [{"type": "point", "position": [0, 1e19, 0]}]})"),
                  {"scene.json: lights[0].position: is beyond +-1e11"});
}

// Found by review: a scene 1e-14 across gave hits at t = 0 (the triangle test's products of
// three coordinates underflow) and a bare mesh 1e-20 across a NaN image. 1e-9 is the floor.
TEST(SceneBadInput, ScenesTooSmallForFloatAreRefused) {
  TempDir dir;
  expect_contains(json_error(dir, R"({"meshes": [{"shape": "box", "min": [0, 0, 0], "max": [1, 1, 1], "transform": {"scale": 1e-12}}]})"),
                  {"scene.json: the scene is only 1.73205e-12 across (its bounds' diagonal); below 1e-9", "scale the scene up"});
  const auto tiny = dir.write("tiny.obj", "v 0 0 0\nv 1e-11 0 0\nv 0 1e-11 0\nf 1 2 3\n");
  expect_contains(input_error_of([&] { load_scene(tiny); }), {"tiny.obj: the scene is only 1.41421e-11 across"});
  // Just above the floor, it loads.
  EXPECT_EQ(load_scene(dir.write("small.obj", "v 0 0 0\nv 1e-9 0 0\nv 0 1e-9 0\nf 1 2 3\n")).triangles.size(), 1u);
}

// The parallel-up check is about directions: lengths far from 1 neither hide nor fake it.
TEST(SceneBadInput, JsonCameraUpOfAnyLength) {
  TempDir dir;
  const std::string tri = R"({"meshes": [{"file": "tri.obj"}], )";
  for (const char* up : {"[0, 0, 1e-30]", "[0, 0, 1e20]", "[1e-7, 0, 1]"})
    expect_contains(json_error(dir, tri + R"("camera": {"eye": [0, 0, 1], "look_at": [0, 0, 0], "up": )" + up + "}}"),
                    {"scene.json: camera.up: is parallel to the view direction"});
  // A long up, a short one, a look_at 1e-30 from the eye: valid, and the frame follows them.
  // The light added for a scene without lights and the default focus distance follow too.
  const std::pair<const char*, Vec3> valid[] = {
      {R"({"eye": [0, 0, 1], "look_at": [0, 0, 0], "up": [0, 1e20, 0]})", {0, 1, 0}},
      {R"({"eye": [0, 0, 1], "look_at": [0, 0, 0], "up": [1e-30, 0, 0]})", {1, 0, 0}},
      {R"({"eye": [0, 0, 1], "look_at": [0, 0, 0], "up": [0, 1e-38, 0]})", {0, 1, 0}},
      {R"({"eye": [0, 0, 0], "look_at": [1e-30, 0, 0], "up": [0, 0, 1]})", {0, 0, 1}},
      {R"({"eye": [0.2, 0.2, 2e-23], "look_at": [0.2, 0.2, 1e-23], "lens_radius": 0.001})", {0, 1, 0}}};
  for (const auto& [camera, up] : valid) {
    const Scene s = load_scene(dir.write("ok.json", tri + R"("camera": )" + camera + "}"));
    const CameraFrame f = camera_frame(s.camera, 1.0f);
    EXPECT_NEAR(dot(f.up, up), 1.0f, 1e-6f) << camera;
    ASSERT_EQ(s.point_lights.size(), 1u);
    EXPECT_TRUE(is_finite(s.point_lights[0].position)) << camera;
    EXPECT_GT(dot(s.point_lights[0].position - s.camera.eye, up), 0.0f) << camera;  // above the camera
    EXPECT_GT(s.camera.focus_distance, 0.0f) << camera;
  }
  // The framing camera of a tiny field of view stands beyond float's reach: said, not a black image.
  expect_contains(json_error(dir, tri + R"("camera": {"fov_deg": 1e-30}})"),
                  {"scene.json: camera.eye (the framing camera's, for this fov_deg; give an eye): is beyond +-1e11"});
}

TEST(SceneBadInput, JsonMeshFileErrorsNameBothFiles) {
  TempDir dir;
  dir.write("tri.obj", kTriangle + "f 1 2 3\n");
  dir.write("bad.obj", kTriangle + "f 1 2 4\n");
  expect_contains(error_loading(dir, "s.json", R"({"meshes": [{"file": "bad.obj"}]})"),
                  {"s.json: meshes[0].file: ", "bad.obj:4: face index 4 out of range (3 vertices)"});
  expect_contains(error_loading(dir, "t.json", R"({"meshes": [{"file": "tri.obj"}, {"file": "missing.ply"}]})"),
                  {"t.json: meshes[1].file: ", "missing.ply: cannot open"});
}

// Found by fuzzing: work quadratic in the size of inputs of a few MB, so a load that never
// seemed to end (100000 keys, materials or warnings: 30 to 80 s). Timed here at half that
// size, which took 7 to 12 s before, with a bound far above the linear time.
double seconds_to_load(const std::filesystem::path& p, Scene& out) {
  const auto start = std::chrono::steady_clock::now();
  out = load_scene(p);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

TEST(SceneBadInput, JsonObjectOfManyKeysIsReadInLinearTimeAndInFileOrder) {
  TempDir dir;
  dir.write("tri.obj", kTriangle + "f 1 2 3\n");
  std::string materials;
  for (int i = 50000; i-- > 0;) materials += (materials.empty() ? "\"m" : ", \"m") + std::to_string(i) + "\": {}";
  Scene s;
  const double t = seconds_to_load(dir.write("keys.json", R"({"meshes": [{"file": "tri.obj"}], "materials": {)" + materials + "}}"), s);
  EXPECT_LT(t, 3.0) << "50000 keys in one object (7 s before)";
  ASSERT_EQ(s.materials.size(), 50001u);  // the mesh's "default", then the file's, in file order
  EXPECT_EQ(s.materials[1].name, "m49999");
  EXPECT_EQ(s.materials[50000].name, "m0");
  // A duplicate among many keys is still found.
  expect_contains(json_error(dir, R"({"meshes": [{"file": "tri.obj"}], "materials": {)" + materials + R"(, "m7": {}}})"),
                  {"scene.json: key \"m7\" appears twice in one object"});
}

TEST(SceneBadInput, MtlOfManyMaterialsIsReadInLinearTime) {
  TempDir dir;
  std::string mtl, obj = "mtllib many.mtl\n" + kTriangle;
  for (int i = 0; i < 50000; ++i) {
    mtl += "newmtl m" + std::to_string(i) + "\nKd 0." + std::to_string(i % 10) + "\n";
    obj += "usemtl m" + std::to_string(49999 - i) + "\nf 1 2 3\n";
  }
  mtl += "newmtl m5\nKd 0.25\n";  // a later definition of a name replaces the first
  dir.write("many.mtl", mtl);
  Scene s;
  const double t = seconds_to_load(dir.write("many.obj", obj), s);
  EXPECT_LT(t, 3.0) << "50000 materials (11 s before)";
  ASSERT_EQ(s.materials.size(), 50000u);
  EXPECT_EQ(s.materials[0].name, "m49999");  // in order of first use
  EXPECT_FLOAT_EQ(s.materials[0].diffuse.x, 0.9f);
  EXPECT_EQ(s.materials[49994].name, "m5");
  EXPECT_FLOAT_EQ(s.materials[49994].diffuse.x, 0.25f);
}

TEST(SceneBadInput, JsonSceneOfAMeshWithManyWarningsIsReadInLinearTime) {
  TempDir dir;
  std::string obj = kTriangle;
  for (int i = 0; i < 50000; ++i) obj += "usemtl undefined" + std::to_string(i) + "\nf 1 2 3\n";
  dir.write("undef.obj", obj);
  Scene s;
  const double t =
      seconds_to_load(dir.write("s.json", R"({"meshes": [{"file": "undef.obj"}, {"file": "undef.obj"}]})"), s);
  EXPECT_LT(t, 3.0) << "50000 warnings (12 s before)";
  ASSERT_EQ(s.warnings.size(), 50001u);  // once each, although the mesh is placed twice; and "no lights"
  expect_contains(s.warnings[0], {"undef.obj:4: material 'undefined0' is not defined in any material library"});
}

// Mutation checks: each case below passed every scene test with a one-line change to the reader
// (named beside it) and fails with it.
TEST(SceneBadInput, ObjErrorsAtTheirBounds) {
  TempDir dir;
  // A forward index names the first line that used it (MaxRef::note kept the last).
  expect_contains(error_loading(dir, "fwd.obj", kTriangle + "f 1 2 9\nf 1 2 9\n"),
                  {"fwd.obj:4: face index 9 out of range (3 vertices)"});
  // "1/" has an empty texcoord index; only v//vn may leave it out.
  expect_contains(error_loading(dir, "slash.obj", kTriangle + "f 1/ 2/ 3/\n"),
                  {"slash.obj:4: face vertex '1/' has an empty index"});
  // One number is a grey in MTL only (read_vec3's allow_one): "v 1" is not (1, 1, 1).
  expect_contains(error_loading(dir, "one.obj", "v 1\n" + kTriangle + "f 2 3 4\n"),
                  {"one.obj:1: ", "vertex: expected 3 numbers, found 1"});
  // Every colour component is checked, the last one too.
  dir.write("blue.mtl", "newmtl a\nKd 0.5 0.5 -0.1\n");
  expect_contains(error_loading(dir, "blue.obj", "mtllib blue.mtl\n" + kTriangle + "usemtl a\nf 1 2 3\n"),
                  {"blue.mtl:2: ", "Kd: colour components must be >= 0"});
}

TEST(SceneBadInput, PlyNegativeCountAndListCoordinate) {
  TempDir dir;
  expect_contains(error_loading(dir, "neg.ply", "ply\nformat ascii 1.0\nelement vertex -1\nproperty float x\n"
                                                "property float y\nproperty float z\nend_header\n"),
                  {"neg.ply:3: element: expected 'element <name> <count>'"});
  // A list named x is no coordinate (it would read as 0).
  expect_contains(error_loading(dir, "listx.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty list uchar float x\n"
                                                  "property float y\nproperty float z\nelement face 1\n"
                                                  "property list uchar int vertex_indices\nend_header\n"
                                                  "1 0 0 0\n1 1 0 0\n1 0 1 0\n3 0 1 2\n"),
                  {"listx.ply:3: vertex element lacks x, y or z properties"});
}

// The column of the nesting error counts an escaped character in a string.
TEST(SceneBadInput, JsonDeepNestingColumnCountsEscapes) {
  TempDir dir;
  const std::string deep = std::string(300, '[') + std::string(300, ']');
  // {"comment": "\"", "x": [[[...: the 257th '[' is at column 22 + 256.
  expect_contains(json_error(dir, R"({"comment": "\"", "x": )" + deep + "}"),
                  {"scene.json: JSON nested deeper than 256 arrays and objects at line 1, column 279"});
}

TEST(SceneBadInput, JsonBoxFlatInZ) {
  TempDir dir;
  expect_contains(json_error(dir, R"({"meshes": [{"shape": "box", "min": [0, 0, 0], "max": [1, 1, 0]}]})"),
                  {"scene.json: meshes[0].max: must exceed min on every axis"});
}

}  // namespace
}  // namespace rayscout
