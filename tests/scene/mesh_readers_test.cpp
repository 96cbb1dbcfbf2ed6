// OBJ, MTL, PLY (ascii and binary) and glTF readers: exact counts, coordinates and order.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include <unistd.h>

#include "rayscout/scene/load_scene.h"
#include "rayscout/scene/mesh.h"
#include "temp_files.h"

namespace rayscout {
namespace {

using testing::expect_contains;
using testing::input_error_of;
using testing::TempDir;

void expect_vec(const Vec3& a, const Vec3& b) {
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.y, b.y);
  EXPECT_EQ(a.z, b.z);
}

void expect_triangle(const Triangle& t, const Vec3& a, const Vec3& b, const Vec3& c) {
  expect_vec(t.v0, a);
  expect_vec(t.v1, b);
  expect_vec(t.v2, c);
}

TEST(ObjReader, ExactCoordinatesAndFanOrder) {
  TempDir dir;
  // A quad and a pentagon: fans (0 1 2)(0 2 3) and (0 1 2)(0 2 3)(0 3 4), in file order.
  const auto p = dir.write("fan.obj",
                           "# test\r\n"
                           "v 0.1 0.2 0.3\r\n"
                           "v 1.5 -2.25 +3e-2\n"
                           "v 1 1 0 1.0\n"        // w is ignored
                           "v 0 1 0   0.5 0.5 0.5\n"  // vertex colours are ignored
                           "vt 0 0\nvn 0 0 1\n"
                           "g quad\ns off\n"
                           "f 1/1/1 2/1/1 3//1 4\n"
                           "v 10 0 0\nv 11 0 0\nv 11 1 0\nv 10.5 2 0\nv 10 1 0\n"
                           "f -5 -4 -3 -2 -1  # pentagon with relative indices\n");
  const Scene s = load_scene(p);
  ASSERT_EQ(s.triangles.size(), 5u);
  const Vec3 a(0.1f, 0.2f, 0.3f), b(1.5f, -2.25f, 0.03f), c(1, 1, 0), d(0, 1, 0);
  expect_triangle(s.triangles[0], a, b, c);
  expect_triangle(s.triangles[1], a, c, d);
  const Vec3 e(10, 0, 0), f(11, 0, 0), g(11, 1, 0), h(10.5f, 2, 0), i(10, 1, 0);
  expect_triangle(s.triangles[2], e, f, g);
  expect_triangle(s.triangles[3], e, g, h);
  expect_triangle(s.triangles[4], e, h, i);
  EXPECT_TRUE(s.warnings.empty());
  // Bare mesh: a framing camera and one point light.
  EXPECT_EQ(s.point_lights.size(), 1u);
  expect_vec(s.camera.look_at, s.bounds().center());
}

// A concave polygon's fan covers area outside it (the chevron A B C D, reflex at D: fan triangle
// A B C covers the notch, A C D is turned over). It is ear-clipped instead: the triangles tile the
// polygon (area 1, not the fan's 3) and keep its winding, in the fan's place among the ids.
void expect_chevron_tiled(const Scene& s, const Vec3& normal) {
  ASSERT_EQ(s.triangles.size(), 4u);  // a triangle, the chevron (2), a triangle
  float area = 0;
  for (size_t t = 1; t <= 2; ++t) {
    EXPECT_GT(dot(s.triangles[t].normal(), normal), 0.0f) << "triangle " << t << " turned over";
    area += s.triangles[t].area();
  }
  EXPECT_FLOAT_EQ(area, 1.0f);
  EXPECT_EQ(s.triangles[0].v0.x, 10.0f);
  EXPECT_EQ(s.triangles[3].v0.x, 20.0f);
}

TEST(ObjReader, ConcavePolygonIsEarClippedNotFanned) {
  TempDir dir;
  const std::string others = "v 10 0 0\nv 11 0 0\nv 10 1 0\nv 20 0 0\nv 21 0 0\nv 20 1 0\n";
  const auto obj = [&](const std::string& corners, const std::string& face) {
    return corners + others + "f 5 6 7\n" + face + "\nf 8 9 10\n";
  };
  // In the xy plane, counter-clockwise seen from +z.
  const std::string xy = "v 0 0 0\nv 2 1 0\nv 0 2 0\nv 1 1 0\n";
  expect_chevron_tiled(load_scene(dir.write("xy.obj", obj(xy, "f 1 2 3 4"))), Vec3(0, 0, 1));
  // Relative indices, in the yz plane, turned so that the projection is mirrored (C B A D).
  const std::string yz = "v 0 0 0\nv 0 1 2\nv 0 2 0\nv 0 1 1\n";
  expect_chevron_tiled(load_scene(dir.write("yz.obj", obj(yz, "f -8 -9 -10 -7"))), Vec3(1, 0, 0));
  // Wound the other way (normal -z), the projection is mirrored before the ear clipping.
  expect_chevron_tiled(load_scene(dir.write("cw.obj", obj(xy, "f 1 4 3 2"))), Vec3(0, 0, -1));
  // A concave polygon that its first vertex sees whole (the L from its reflex corner) keeps its fan.
  const Scene l = load_scene(dir.write("l.obj", "v 1 1 0\nv 1 2 0\nv 0 2 0\nv 0 0 0\nv 2 0 0\nv 2 1 0\nf 1 2 3 4 5 6\n"));
  ASSERT_EQ(l.triangles.size(), 4u);
  for (size_t t = 0; t < 4; ++t) EXPECT_EQ(l.triangles[t].v0, Vec3(1, 1, 0));
}

TEST(PlyReader, ConcavePolygonIsEarClippedNotFanned) {
  TempDir dir;
  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 10\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 3\nproperty list uchar int vertex_indices\nend_header\n"
      "10 0 0\n11 0 0\n10 1 0\n0 0 0\n2 1 0\n0 2 0\n1 1 0\n20 0 0\n21 0 0\n20 1 0\n"
      "3 0 1 2\n4 3 4 5 6\n3 7 8 9\n";
  expect_chevron_tiled(load_scene(dir.write("c.ply", text)), Vec3(0, 0, 1));
}

// A bare mesh with emitters is lit by them alone, as a JSON scene without lights: a point light
// added beside them made a path-traced Cornell box 2-7 times too bright.
TEST(ObjReader, BareMeshWithEmittersGetsNoPointLight) {
  TempDir dir;
  dir.write("lamp.mtl", "newmtl lamp\nKd 0 0 0\nKe 5 5 5\nnewmtl wall\nKd 0.5 0.5 0.5\n");
  const Scene s = load_scene(dir.write("lit.obj", "mtllib lamp.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                                  "usemtl wall\nf 1 2 3\nusemtl lamp\nf 1 2 4\n"));
  ASSERT_EQ(s.triangles.size(), 2u);
  EXPECT_EQ(s.emissive_triangles.size(), 1u);
  EXPECT_TRUE(s.point_lights.empty());
  expect_vec(s.camera.look_at, s.bounds().center());
}

TEST(ObjReader, ClassicMacLineEndsAreLines) {
  // CR alone ends a line in a file without LF; it was read as one line (one vertex, no faces).
  TempDir dir;
  const Scene s = load_scene(dir.write("cr.obj", "# classic Mac\rv 0 0 0\rv 2 0 0\rv 0 3 0\rf 1 2 3\r"));
  ASSERT_EQ(s.triangles.size(), 1u);
  expect_triangle(s.triangles[0], Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 3, 0));
  expect_contains(input_error_of([&] { load_scene(dir.write("bad.obj", "v 0 0 0\rv 1 0 0\rf 1 2 9\r")); }),
                  {"bad.obj:3: "});
}

TEST(ObjReader, Utf8ByteOrderMarkIsSkipped) {
  TempDir dir;
  const Scene s = load_scene(dir.write("bom.obj", "\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
  EXPECT_EQ(s.triangles.size(), 1u);
}

TEST(ObjReader, ForwardReferencesAreAllowed) {
  TempDir dir;
  const Scene s = load_scene(dir.write("fwd.obj", "f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"));
  ASSERT_EQ(s.triangles.size(), 1u);
  expect_triangle(s.triangles[0], {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
}

TEST(ObjReader, DegenerateTrianglesDroppedAndCounted) {
  TempDir dir;
  // Faces: good, repeated index, collinear, good, coincident positions.
  const auto p = dir.write("deg.obj",
                           "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nv 0 0 0\n"
                           "f 1 2 3\nf 1 1 2\nf 1 2 4\nf 3 2 1\nf 1 5 2\n");
  const Scene s = load_scene(p);
  ASSERT_EQ(s.triangles.size(), 2u);
  expect_triangle(s.triangles[0], {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  expect_triangle(s.triangles[1], {0, 1, 0}, {1, 0, 0}, {0, 0, 0});
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("dropped 3 degenerate (zero-area) triangles"), std::string::npos) << s.warnings[0];
  // The reader itself keeps every face; only the scene drops them.
  EXPECT_EQ(read_mesh(p).faces.size(), 5u);
}

TEST(ObjReader, MtlMaterialMapping) {
  TempDir dir;
  dir.write("m.mtl",
            "newmtl matte\n  Kd 0.5 0.25 0.125 # comment\n  Ks 0 0 0\n  Ns 10\n  illum 2\n\n"
            "newmtl shiny\nKd 0.1 0.1 0.1\nKs 0.4 0.4 0.4\nNs 200\nillum 2\n"
            "newmtl chrome\nKd 0 0 0\nKs 0.9 0.9 0.9\nNs 10\nillum 3\n"
            "newmtl polished\nKs 0.8\nNs 5000\n"
            "newmtl lamp \nKd 0.7 0.7 0.7\nKe 17 12 4\nmap_Kd textures\\lamp.tga\n");
  const auto p = dir.write("m.obj",
                           "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                           "f 1 2 3\nusemtl matte\nf 2 4 3\nusemtl shiny\nf 1 2 3\nusemtl chrome\nf 1 2 3\n"
                           "usemtl polished\nf 1 2 3\nusemtl lamp\nf 1 2 3\nf 2 4 3\nusemtl matte\nf 1 2 3\n");
  const Scene s = load_scene(p);
  ASSERT_EQ(s.triangles.size(), 8u);
  std::vector<std::string> names;
  for (uint32_t t = 0; t < 8; ++t) names.push_back(s.material_of(t).name);
  EXPECT_EQ(names, (std::vector<std::string>{"default", "matte", "shiny", "chrome", "polished", "lamp", "lamp", "matte"}));
  const Material& matte = s.material_of(1);
  EXPECT_EQ(matte.type, Material::Type::Diffuse);
  expect_vec(matte.diffuse, {0.5f, 0.25f, 0.125f});
  const Material& shiny = s.material_of(2);
  EXPECT_EQ(shiny.type, Material::Type::Glossy);
  expect_vec(shiny.specular, Vec3(0.4f));
  EXPECT_EQ(shiny.exponent, 200.0f);
  EXPECT_EQ(s.material_of(3).type, Material::Type::Mirror);  // illum 3
  EXPECT_EQ(s.material_of(4).type, Material::Type::Mirror);  // Ns >= 1000
  expect_vec(s.material_of(4).specular, Vec3(0.8f));          // one value = grey
  EXPECT_TRUE(s.material_of(5).emissive());
  expect_vec(s.material_of(5).emission, {17, 12, 4});
  EXPECT_EQ(s.emissive_triangles, (std::vector<uint32_t>{5, 6}));
  EXPECT_FALSE(s.material_of(0).emissive());
}

// The MTL rules at their bounds: illum 7 is a mirror (as 3 and 5), Ns 1000 is one, and illum
// 10 is the last model. Each passed the tests above when moved by one.
TEST(ObjReader, MtlMirrorRulesAtTheirBounds) {
  TempDir dir;
  dir.write("b.mtl", "newmtl seven\nKs 0.5\nNs 10\nillum 7\nnewmtl ns1000\nKs 0.5\nNs 1000\n"
                     "newmtl ten\nKs 0.5\nNs 10\nillum 10\n");
  const Scene s = load_scene(dir.write("b.obj", "mtllib b.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                                "usemtl seven\nf 1 2 3\nusemtl ns1000\nf 1 2 3\nusemtl ten\nf 1 2 3\n"));
  ASSERT_EQ(s.triangles.size(), 3u);
  EXPECT_EQ(s.material_of(0).type, Material::Type::Mirror);
  EXPECT_EQ(s.material_of(1).type, Material::Type::Mirror);
  EXPECT_EQ(s.material_of(2).type, Material::Type::Glossy);
}

// MTL data from the wild may reflect more than arrives (CornellBox-Glossy's sphere: Kd up to
// 0.663 + Ks 0.9): Kd and Ks are scaled by 1 / max(Kd + Ks) with a warning naming the file,
// the newmtl line and the material. A mirror's unused Kd does not count.
TEST(ObjReader, MaterialsReflectingMoreThanArrivesAreScaledWithAWarning) {
  TempDir dir;
  dir.write("m.mtl",
            "newmtl sphere\nNs 400\nillum 2\nKd 0.4860 0.6310 0.6630\nKs 0.9 0.9 0.9\n"
            "newmtl bright\nKd 1.25 0.5 0.5\n"
            "newmtl mirror\nKd 0.5\nKs 0.9\nillum 3\n"
            "newmtl plain\nKd 0.5\nKs 0.5\nNs 10\n");
  const Scene s = load_scene(dir.write("m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                                "usemtl sphere\nf 1 2 3\nusemtl bright\nf 1 2 3\n"
                                                "usemtl mirror\nf 1 2 3\nusemtl plain\nf 1 2 3\n"));
  ASSERT_EQ(s.triangles.size(), 4u);
  ASSERT_EQ(s.warnings.size(), 2u);
  EXPECT_NE(s.warnings[0].find("m.mtl:1: material 'sphere': Kd + Ks reaches 1.563 in a channel"), std::string::npos)
      << s.warnings[0];
  EXPECT_NE(s.warnings[0].find("Kd and Ks scaled by 1/1.563"), std::string::npos) << s.warnings[0];
  EXPECT_NE(s.warnings[1].find("m.mtl:6: material 'bright'"), std::string::npos) << s.warnings[1];
  const Material& sphere = s.material_of(0);
  EXPECT_EQ(sphere.type, Material::Type::Glossy);
  expect_vec(sphere.diffuse, Vec3{0.486f, 0.631f, 0.663f} * (1.0f / 1.563f));
  expect_vec(sphere.specular, Vec3(0.9f / 1.563f));
  EXPECT_NEAR(max_component(sphere.diffuse + sphere.specular), 1.0f, 1e-6f);
  expect_vec(s.material_of(1).diffuse, {1.0f, 0.4f, 0.4f});
  expect_vec(s.material_of(2).specular, Vec3(0.9f));  // a mirror reflects Ks only
  expect_vec(s.material_of(3).diffuse, Vec3(0.5f));   // Kd + Ks = 1 exactly is fine
}

TEST(ObjReader, MissingMtlAndUnknownMaterialAreWarnings) {
  TempDir dir;
  const Scene s = load_scene(dir.write("w.obj", "mtllib nothere.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\n"));
  ASSERT_EQ(s.triangles.size(), 1u);
  EXPECT_EQ(s.material_of(0).name, "x");
  ASSERT_EQ(s.warnings.size(), 2u);
  EXPECT_NE(s.warnings[0].find("w.obj:1: material library 'nothere.mtl' not found"), std::string::npos);
  // The missing library explains the undefined name; the warning names its first usemtl.
  EXPECT_NE(s.warnings[1].find("w.obj:5: 1 material ('x') not defined, as a material library is missing; it gets a grey diffuse"),
            std::string::npos) << s.warnings[1];
  // Every name of a missing library in one warning, not one each (Crytek Sponza without its MTL: 25).
  std::string many = "mtllib nothere.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n";
  for (int i = 0; i < 7; ++i) many += "usemtl m" + std::to_string(i) + "\nf 1 2 3\n";
  const Scene m = load_scene(dir.write("many.obj", many));
  ASSERT_EQ(m.warnings.size(), 2u);
  EXPECT_NE(m.warnings[1].find("many.obj:5: 7 materials ('m0', 'm1', 'm2', 'm3', 'm4', ...) not defined, as a material library "
                               "is missing; they get a grey diffuse"),
            std::string::npos) << m.warnings[1];
  // Without a missing library, an undefined name is most likely a typo: a warning of its own.
  const Scene u = load_scene(dir.write("u.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\nusemtl y\nf 1 2 3\n"));
  ASSERT_EQ(u.warnings.size(), 2u);
  EXPECT_NE(u.warnings[0].find("u.obj:4: material 'x' is not defined in any material library; using a grey diffuse"),
            std::string::npos) << u.warnings[0];
}

// mtllib names several libraries, or one whose name holds spaces when that file exists.
TEST(ObjReader, MtllibNamesSeveralLibrariesOrOneWithSpaces) {
  TempDir dir;
  dir.write("my lib.mtl", "newmtl a\nKd 0.1\n");
  dir.write("b.mtl", "newmtl b\nKd 0.2\n");
  dir.write("c.mtl", "newmtl c\nKd 0.3\n");
  const Scene s = load_scene(dir.write("libs.obj", "mtllib my lib.mtl\nmtllib b.mtl c.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                                   "usemtl a\nf 1 2 3\nusemtl b\nf 1 2 3\nusemtl c\nf 1 2 3\n"));
  ASSERT_EQ(s.triangles.size(), 3u);
  EXPECT_EQ(s.material_of(0).diffuse, Vec3(0.1f));
  EXPECT_EQ(s.material_of(1).diffuse, Vec3(0.2f));
  EXPECT_EQ(s.material_of(2).diffuse, Vec3(0.3f));
  EXPECT_TRUE(s.warnings.empty()) << s.warnings[0];
}

// A material defined twice: the later definition is used, and said. An illumination model
// outside the MTL's 0..10 is an error at its line, and an unreadable library one at the mtllib.
TEST(ObjReader, RedefinedMaterialWarnsAndBadIllumOrUnreadableLibraryIsAnError) {
  TempDir dir;
  dir.write("twice.mtl", "newmtl m\nKd 0.2\nnewmtl m\nKd 0.6\n");
  const Scene s = load_scene(dir.write("twice.obj", "mtllib twice.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n"));
  EXPECT_EQ(s.material_of(0).diffuse, Vec3(0.6f));
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("twice.mtl:3: material 'm' defined again; this later definition is used"),
            std::string::npos) << s.warnings[0];
  dir.write("illum.mtl", "newmtl m\nillum 99999999999\n");
  expect_contains(input_error_of([&] { read_mesh(dir.write("illum.obj", "mtllib illum.mtl\nv 0 0 0\n")); }),
                  {"illum.mtl:2: illum 99999999999: the MTL illumination models are 0 to 10"});
  if (::geteuid() != 0) {  // root reads any file
    const std::filesystem::path locked = dir.write("locked.mtl", "newmtl m\n");
    std::filesystem::permissions(locked, std::filesystem::perms::none);
    expect_contains(input_error_of([&] { read_mesh(dir.write("locked.obj", "v 0 0 0\nmtllib locked.mtl\n")); }),
                    {"locked.obj:2: material library 'locked.mtl' cannot be read"});
  }
}

// A library named again was read again, each time warning that every one of its
// materials was "defined again" (3000 mtllib lines of a 1000-material MTL: 3M warnings, 388 MB).
// It is read once, whatever the spelling of its path; a missing one is said once.
TEST(ObjReader, MaterialLibraryNamedAgainIsReadOnce) {
  TempDir dir;
  std::string mtl;
  for (int i = 0; i < 1000; ++i) mtl += "newmtl m" + std::to_string(i) + "\nKd 0.5\n";
  dir.write("many.mtl", mtl);
  std::filesystem::create_directory(dir.path() / "sub");
  std::string obj = "mtllib many.mtl many.mtl\nmtllib ./many.mtl\nmtllib sub/../many.mtl\nmtllib gone.mtl\n";
  for (int i = 0; i < 300; ++i) obj += "mtllib many.mtl\nmtllib gone.mtl\n";
  const Scene s = load_scene(dir.write("again.obj", obj + "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m7\nf 1 2 3\n"));
  ASSERT_EQ(s.warnings.size(), 1u);
  expect_contains(s.warnings[0], {"again.obj:4: material library 'gone.mtl' not found"});
  EXPECT_EQ(s.material_of(0).name, "m7");
  EXPECT_EQ(s.material_of(0).diffuse, Vec3(0.5f));
  // An OBJ named without a folder ("again.obj", not "./again.obj") said a missing
  // library twice, once as "gone.mtl" and once as "./gone.mtl".
  const std::filesystem::path cwd = std::filesystem::current_path();
  std::filesystem::current_path(dir.path());
  dir.write("bare.obj", "mtllib gone.mtl\nmtllib ./gone.mtl\nmtllib sub/../gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const Scene bare = load_scene("bare.obj");
  std::filesystem::current_path(cwd);
  ASSERT_EQ(bare.warnings.size(), 1u);
  expect_contains(bare.warnings[0], {"bare.obj:1: material library 'gone.mtl' not found"});
}

// "kd 1 0 0" (lower case) was ignored without a word, and the material stayed grey. An
// unknown MTL key is warned about once per file; the statements rayscout ignores on purpose are not.
TEST(ObjReader, UnknownMtlStatementIsWarnedAboutOnce) {
  TempDir dir;
  dir.write("u.mtl", "newmtl red\nkd 1 0 0\nKa 0 0 0\nNi 1.5\nd 1\nTr 0\nTf 1 1 1\nmap_Kd a.png\nmap_bump b.png\n"
                     "bump b.png\ndisp c.png\ndecal d.png\nrefl -type sphere e.png\nsharpness 60\nKm 1\n"
                     "Pr 0.5\nPm 0\nPs 0\nPc 0\nPcr 0\naniso 0\nanisor 0\nnorm n.png\nkd 0 1 0\nTs 0.5\nNS 10\n");
  const Scene s = load_scene(dir.write("u.obj", "mtllib u.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n"));
  ASSERT_EQ(s.warnings.size(), 3u);
  EXPECT_EQ(s.warnings[0], (dir.path() / "u.mtl").string() +
                               ":2: unknown MTL statement 'kd' ignored; keys are case-sensitive: did you mean 'Kd'?");
  expect_contains(s.warnings[1], {"u.mtl:25: unknown MTL statement 'Ts' ignored"});
  EXPECT_EQ(s.warnings[1].find("did you mean"), std::string::npos) << s.warnings[1];
  expect_contains(s.warnings[2], {"u.mtl:26: unknown MTL statement 'NS' ignored; keys are case-sensitive: did you mean 'Ns'?"});
  EXPECT_EQ(s.material_of(0).diffuse, Vec3(0.8f));  // the default grey, as said
}

// OBJ refused 1e-50 ("out of float range") where JSON reads 0. Every text reader now
// gives what JSON gives: the nearest float (a denormal, or 0 with the sign); overflow stays an error.
TEST(ObjReader, UnderflowGivesTheNearestFloatAsInJson) {
  TempDir dir;
  const Vec3 tiny(0.0f, float(1e-40), -0.0f);
  ASSERT_NE(tiny.y, 0.0f);  // a denormal
  const Scene json = load_scene(dir.write("q.json", R"({"meshes": [{"shape": "quad", "corner": [1e-50, 1e-40, -1e-400],
      "edge1": [1, 0, 0], "edge2": [0, 1, 0]}]})"));
  expect_vec(json.triangles[0].v0, tiny);
  EXPECT_TRUE(std::signbit(json.triangles[0].v0.z));
  dir.write("u.mtl", "newmtl m\nKd 1e-50 0.5 7e-46\nNs 1e-60\n");
  const Mesh obj = read_mesh(dir.write("u.obj", "mtllib u.mtl\nv 1e-50 1e-40 -1e-400\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n"));
  expect_vec(obj.positions[0], tiny);
  EXPECT_TRUE(std::signbit(obj.positions[0].z));
  expect_vec(obj.materials[0].diffuse, {0.0f, 0.5f, 0.0f});
  EXPECT_EQ(obj.materials[0].exponent, 0.0f);
  const Mesh ply = read_mesh(dir.write("u.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                                "property float y\nproperty double z\nelement face 1\n"
                                                "property list uchar int vertex_indices\nend_header\n"
                                                "1e-50 1e-40 -1e-400\n1 0 0\n0 1 0\n3 0 1 2\n"));
  expect_vec(ply.positions[0], tiny);
  // Overflow is still an error.
  expect_contains(input_error_of([&] { read_mesh(dir.write("big.obj", "v 0 0 1e39\n")); }),
                  {"big.obj:1: vertex: coordinate 1e39 is out of float range"});
  expect_contains(input_error_of([&] { read_mesh(dir.write("big.ply", "ply\nformat ascii 1.0\nelement vertex 1\n"
                                                                      "property float x\nproperty float y\n"
                                                                      "property float z\nend_header\n0 -1e39 0\n")); }),
                  {"big.ply:8: '-1e39' is out of float range"});
  // A double property holds 1e39 exactly; it overflows only as a float vertex.
  expect_contains(input_error_of([&] { read_mesh(dir.write("dbl.ply", "ply\nformat ascii 1.0\nelement vertex 1\n"
                                                                      "property double x\nproperty double y\n"
                                                                      "property double z\nend_header\n0 1e39 0\n")); }),
                  {"dbl.ply:8: vertex coordinate 1e+39 is out of float range"});
  // A colour's number is a component, not a coordinate.
  dir.write("hot.mtl", "newmtl m\nKe 1e39 0 0\n");
  expect_contains(input_error_of([&] { read_mesh(dir.write("hot.obj", "mtllib hot.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                                                      "usemtl m\nf 1 2 3\n")); }),
                  {"hot.mtl:2: Ke: component 1e39 is out of float range"});
}

// The same mesh (a quad and a triangle, coordinates exact in float) as PLY of each format.
struct PlyMesh {
  std::vector<Vec3> v = {{0.5f, -1.25f, 3.0f}, {2.0f, 0.0f, 0.125f}, {1.0f, 1.0f, 1.0f}, {-4.0f, 2.5f, 0.0f}};
  std::vector<std::vector<int>> faces = {{0, 1, 2, 3}, {3, 2, 0}};
};

std::string ply_header(const std::string& format, const char* index_type) {
  return "ply\nformat " + format + " 1.0\ncomment made by a test\nelement vertex 4\nproperty float x\n"
         "property double y\nproperty float z\nproperty uchar red\nelement face 2\nproperty list uchar " +
         index_type + " vertex_indices\nproperty int flags\nelement extra 1\nproperty list int float stuff\nend_header\n";
}

template <typename T>
void put(std::string& out, T value, bool big) {
  char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  if (big) std::reverse(b, b + sizeof(T));
  out.append(b, sizeof(T));
}

std::string binary_ply(bool big) {
  PlyMesh m;
  std::string s = ply_header(big ? "binary_big_endian" : "binary_little_endian", "uint");
  for (const auto& v : m.v) {
    put<float>(s, v.x, big);
    put<double>(s, double(v.y), big);
    put<float>(s, v.z, big);
    put<uint8_t>(s, 200, big);
  }
  for (const auto& f : m.faces) {
    put<uint8_t>(s, uint8_t(f.size()), big);
    for (int i : f) put<uint32_t>(s, uint32_t(i), big);
    put<int32_t>(s, -7, big);
  }
  put<int32_t>(s, 2, big);
  put<float>(s, 1.0f, big);
  put<float>(s, 2.0f, big);
  return s;
}

void expect_ply_mesh(const Scene& s) {
  PlyMesh m;
  ASSERT_EQ(s.triangles.size(), 3u);
  expect_triangle(s.triangles[0], m.v[0], m.v[1], m.v[2]);
  expect_triangle(s.triangles[1], m.v[0], m.v[2], m.v[3]);
  expect_triangle(s.triangles[2], m.v[3], m.v[2], m.v[0]);
}

TEST(PlyReader, AsciiRoundTrip) {
  TempDir dir;
  const std::string text = ply_header("ascii", "int") +
                           "0.5 -1.25 3 200\n2 0 0.125 200\n1 1 1 200\n-4 2.5 0 200\n"
                           "4 0 1 2 3 -7\n3 3 2 0 -7\n2 1.0 2.0\n";
  expect_ply_mesh(load_scene(dir.write("a.ply", text)));
  // Windows line ends too.
  std::string crlf;
  for (char c : text) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  expect_ply_mesh(load_scene(dir.write("crlf.ply", crlf)));
  // Classic Mac line ends: the line end is taken from the magic line.
  std::string cr = text;
  std::replace(cr.begin(), cr.end(), '\n', '\r');
  expect_ply_mesh(load_scene(dir.write("cr.ply", cr)));
  cr[cr.find("4 0 1 2 3")] = '5';
  expect_contains(input_error_of([&] { load_scene(dir.write("bad_cr.ply", cr)); }), {"bad_cr.ply:19:"});
}

// docs/scene-format.md: the face list may be named vertex_index, and the sized type names
// (int8 ... float64) are aliases of char ... double.
TEST(PlyReader, VertexIndexListAndSizedTypeNames) {
  TempDir dir;
  const Mesh m = read_mesh(dir.write("sized.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float64 x\n"
                                                   "property float32 y\nproperty int8 z\nproperty uint16 skipped\n"
                                                   "element face 1\nproperty list uint8 int32 vertex_index\nend_header\n"
                                                   "0.5 0 -1 65535\n1 0 -128 0\n0 1.25 127 0\n3 2 1 0\n"));
  ASSERT_EQ(m.positions.size(), 3u);
  expect_vec(m.positions[0], {0.5f, 0, -1});
  expect_vec(m.positions[1], {1, 0, -128});
  expect_vec(m.positions[2], {0, 1.25f, 127});
  ASSERT_EQ(m.faces.size(), 1u);
  EXPECT_EQ(m.faces[0], (std::array<uint32_t, 3>{2, 1, 0}));
  // An int8 holds -128 to 127, as a char does.
  expect_contains(input_error_of([&] {
                    read_mesh(dir.write("big.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                                   "property float y\nproperty int8 z\nelement face 1\n"
                                                   "property list uchar int vertex_index\nend_header\n"
                                                   "0 0 128\n1 0 0\n0 1 0\n3 0 1 2\n"));
                  }),
                  {"big.ply:10: '128' is out of range for char (-128 to 127)"});
}

// The format is told by the extension in any case: ".OBJ" is an OBJ file, ".Json" a scene.
TEST(ReadMesh, ExtensionInAnyCase) {
  TempDir dir;
  EXPECT_EQ(load_scene(dir.write("TRI.OBJ", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")).triangles.size(), 1u);
  EXPECT_EQ(load_scene(dir.write("s.Json", R"({"meshes": [{"file": "TRI.OBJ"}]})")).triangles.size(), 1u);
  expect_contains(input_error_of([&] { load_scene(dir.write("mesh.stl", "solid")); }),
                  {"mesh.stl: unknown mesh format '.stl' (expected .obj, .ply, .gltf, .glb or a .json scene)"});
  expect_contains(input_error_of([&] { load_scene(dir.write("mesh", "v 0 0 0")); }),
                  {"mesh: no file extension to tell the format by (expected .obj, .ply, .gltf, .glb or a .json scene)"});
}

TEST(PlyReader, BinaryAfterClassicMacHeader) {
  TempDir dir;
  std::string ply = binary_ply(false);
  const size_t body = ply.find("end_header\n") + 11;
  std::replace(ply.begin(), ply.begin() + body, '\n', '\r');
  expect_ply_mesh(load_scene(dir.write("cr_le.ply", ply)));
}

TEST(PlyReader, BinaryLittleAndBigEndianRoundTrip) {
  TempDir dir;
  expect_ply_mesh(load_scene(dir.write("le.ply", binary_ply(false))));
  expect_ply_mesh(load_scene(dir.write("be.ply", binary_ply(true))));
}

std::string base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    uint32_t n = uint32_t(uint8_t(in[i])) << 16 | uint32_t(uint8_t(in[i + 1])) << 8 | uint8_t(in[i + 2]);
    for (int s = 18; s >= 0; s -= 6) out += k[(n >> s) & 63];
  }
  if (i + 1 == in.size()) {
    uint32_t n = uint32_t(uint8_t(in[i])) << 16;
    out += k[(n >> 18) & 63]; out += k[(n >> 12) & 63]; out += "==";
  } else if (i + 2 == in.size()) {
    uint32_t n = uint32_t(uint8_t(in[i])) << 16 | uint32_t(uint8_t(in[i + 1])) << 8;
    out += k[(n >> 18) & 63]; out += k[(n >> 12) & 63]; out += k[(n >> 6) & 63]; out += '=';
  }
  return out;
}

// A glTF whose mesh 0 is the embedded triangle (0,0,0), (1,0,0), (0,1,0); `members` adds the
// "scenes" and "nodes" (and any "materials"), `primitive` extra fields of its primitive.
std::string triangle_gltf(const std::string& members, const std::string& primitive = "") {
  std::string buf;
  for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) put<float>(buf, f, false);
  for (uint16_t i : {0, 1, 2}) put<uint16_t>(buf, i, false);
  buf.append(2, '\0');
  return R"({"asset": {"version": "2.0"}, "scene": 0, )" + members + R"(,
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1)" + primitive + R"(}]}],
    "buffers": [{"byteLength": 44, "uri": "data:application/octet-stream;base64,)" + base64(buf) + R"("}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0,0,0], "max": [1,1,0]},
                  {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]})";
}

TEST(GltfReader, EmbeddedTriangleWithNodeTranslation) {
  TempDir dir;
  const std::string gltf = triangle_gltf(R"("scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "translation": [0, 0, 5]}],
    "materials": [{"name": "glow", "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1]}, "emissiveFactor": [1, 2, 3]}])",
                                         R"(, "material": 0)");
  const Scene s = load_scene(dir.write("t.gltf", gltf));
  ASSERT_EQ(s.triangles.size(), 1u);
  expect_triangle(s.triangles[0], {0, 0, 5}, {1, 0, 5}, {0, 1, 5});
  EXPECT_EQ(s.material_of(0).name, "glow");
  expect_vec(s.material_of(0).emission, {1, 2, 3});
  EXPECT_EQ(s.emissive_triangles.size(), 1u);
  // assimp's default material (for primitives without one) is not listed: "glow" is all.
  EXPECT_EQ(s.materials.size(), 1u);
}

// Of several scenes, the default one ("scene") is loaded, else the first (docs/scene-format.md).
TEST(GltfReader, DefaultSceneElseTheFirst) {
  TempDir dir;
  const std::string members = R"("scenes": [{"nodes": [0]}, {"nodes": [1]}],
    "nodes": [{"mesh": 0, "translation": [0, 0, 5]}, {"mesh": 0, "translation": [0, 0, 9]}])";
  std::string gltf = triangle_gltf(members);
  EXPECT_EQ(load_scene(dir.write("first.gltf", gltf)).triangles[0].v0.z, 5.0f);
  gltf.replace(gltf.find(R"("scene": 0)"), 10, R"("scene": 1)");
  EXPECT_EQ(load_scene(dir.write("second.gltf", gltf)).triangles[0].v0.z, 9.0f);
  gltf.erase(gltf.find(R"("scene": 1, )"), 12);
  EXPECT_EQ(load_scene(dir.write("none.gltf", gltf)).triangles[0].v0.z, 5.0f);
}

// A file without scenes is a library of assets, not a scene (glTF 2.0 sec. 3.5.1: it "SHOULD be
// treated as a library of individual entities"): refused, saying so, rather than with assimp's
// "No scene" (given for "scenes": [] too).
TEST(GltfReader, FileWithoutScenesIsRefusedAsALibrary) {
  TempDir dir;
  for (const char* scenes : {"", R"("scenes": [], )"}) {
    std::string gltf = triangle_gltf(std::string(scenes) + R"("nodes": [{"mesh": 0}])");
    gltf.erase(gltf.find(R"("scene": 0, )"), 12);
    testing::expect_contains(testing::input_error_of([&] { load_scene(dir.write("lib.gltf", gltf)); }),
                             {"lib.gltf: no scenes: a glTF file without scenes is a library of assets"});
  }
}

// KHR_materials_emissive_strength scales emissiveFactor, per material, in file order.
TEST(GltfReader, EmissiveStrength) {
  TempDir dir;
  const std::string gltf = triangle_gltf(R"("scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "materials": [{"name": "dim", "emissiveFactor": [1, 1, 1]},
                  {"name": "bright", "emissiveFactor": [1, 0.5, 0.25],
                   "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}}},
                  {"emissiveFactor": [1, 1, 1], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 2}}},
                  {"name": "twin", "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 2}}},
                  {"name": "twin"},
                  {"name": "n\u0000ul", "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 2}}},
                  {"name": ")" + std::string(1024, 'x') + R"(", "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 2}}}])",
                                         R"(, "material": 1)");
  const Scene s = load_scene(dir.write("e.gltf", gltf));
  EXPECT_EQ(s.material_of(0).name, "bright");
  expect_vec(s.material_of(0).emission, {4, 2, 1});
  // Materials that cannot be found again by name after assimp's import: said, not silently lost.
  ASSERT_EQ(s.warnings.size(), 4u);
  testing::expect_contains(s.warnings[0], {"e.gltf: materials[2]: KHR_materials_emissive_strength ignored (it has no name"});
  testing::expect_contains(s.warnings[1], {"e.gltf: materials[3]: KHR_materials_emissive_strength ignored (its name is not unique"});
  testing::expect_contains(s.warnings[2], {"e.gltf: materials[5]: KHR_materials_emissive_strength ignored (its name holds a NUL"});
  testing::expect_contains(s.warnings[3], {"e.gltf: materials[6]: KHR_materials_emissive_strength ignored (assimp cuts its name"});
  // A strength beyond float range is an error, not an infinite light.
  const std::string huge = triangle_gltf(R"("scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "materials": [{"name": "a", "emissiveFactor": [1, 1, 1], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 1e39}}}])",
                                         R"(, "material": 0)");
  testing::expect_contains(testing::input_error_of([&] { load_scene(dir.write("h.gltf", huge)); }),
                           {"h.gltf: materials[0]: emissiveStrength must be a number in [0, 3.4e38]"});
}

// Colours as in MTL and JSON: negative or beyond float range is an error, not negative or NaN radiance.
TEST(GltfReader, NegativeOrHugeColoursAreErrors) {
  TempDir dir;
  auto with_material = [](const std::string& material) {
    return triangle_gltf(R"("scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}], "materials": [)" + material + "]",
                         R"(, "material": 0)");
  };
  const std::pair<const char*, const char*> cases[] = {
      {R"({"name": "b", "pbrMetallicRoughness": {"baseColorFactor": [-1, 0.5, 0.5, 1]}})",
       "n.gltf: material \"b\": base colour components must be >= 0"},
      {R"({"name": "e", "emissiveFactor": [-1, 0, 2]})", "n.gltf: material \"e\": emission components must be >= 0"},
      {R"({"name": "h", "pbrMetallicRoughness": {"baseColorFactor": [1e39, 0.5, 0.5, 1]}})",
       "n.gltf: material \"h\": base colour beyond float range"},
      // A name quoted in a message shows its control bytes escaped.
      {R"({"name": "esc\u001b[2J", "emissiveFactor": [-1, 0, 2]})",
       "n.gltf: material \"esc\\x1b[2J\": emission components must be >= 0"},
  };
  for (const auto& [material, message] : cases)
    testing::expect_contains(testing::input_error_of([&] { load_scene(dir.write("n.gltf", with_material(material))); }),
                             {message});
}

// A file assimp reads though it is not strict glTF loads as before: a Latin-1 name is not
// UTF-8, so nlohmann cannot read the strengths (a warning), but assimp reads the rest.
TEST(GltfReader, WhatAssimpReadsStillLoads) {
  TempDir dir;
  std::string latin1 = triangle_gltf(R"("scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "materials": [{"name": "caf)" + std::string("\xE9") + R"(", "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 2}}}])",
                                     R"(, "material": 0)");
  const Scene s = load_scene(dir.write("l.gltf", latin1));
  EXPECT_EQ(s.triangles.size(), 1u);
  ASSERT_EQ(s.warnings.size(), 1u);
  testing::expect_contains(s.warnings[0], {"l.gltf: KHR_materials_emissive_strength ignored: invalid JSON"});
}

// A broken container is named as such, with the JSON parser's line and column, not assimp's
// "No suitable reader found".
TEST(GltfReader, BrokenContainersSayWhatIsWrong) {
  TempDir dir;
  expect_contains(input_error_of([&] { load_scene(dir.write("bad.gltf", "{\"asset\":\n  {\"version\": \"2.0\"},")); }),
                  {"bad.gltf: invalid JSON: parse error at line 2"});
  expect_contains(input_error_of([&] { load_scene(dir.write("a.glb", "GLTF\x02\0\0\0")); }),
                  {"a.glb: not a binary glTF file"});
  expect_contains(input_error_of([&] { load_scene(dir.write("s.glb", "glTF\x02")); }),
                  {"s.glb: truncated: 5 bytes, shorter than the 12-byte header"});
  std::string glb("glTF\x02\0\0\0\xff\0\0\0", 12);
  expect_contains(input_error_of([&] { load_scene(dir.write("b.glb", glb)); }),
                  {"b.glb: truncated: the header declares 255 bytes, the file has 12"});
  glb = std::string("glTF\x02\0\0\0\x0c\0\0\0", 12);
  expect_contains(input_error_of([&] { load_scene(dir.write("e.glb", glb)); }), {"e.glb: the first chunk is not a complete JSON chunk"});
  glb = std::string("glTF\x02\0\0\0\x1c\0\0\0\x10\0\0\0JSON{}      ", 28);
  expect_contains(input_error_of([&] { load_scene(dir.write("c.glb", glb)); }), {"c.glb: truncated: the JSON chunk declares 16 bytes, the file has 8 after the chunk header"});
  expect_contains(input_error_of([&] { load_scene(dir.write("bom.gltf", "\xEF\xBB\xBF" + triangle_gltf(R"("scenes": [])"))); }),
                  {"bom.gltf: starts with a byte order mark"});
  expect_contains(input_error_of([&] { load_scene(dir.write("arr.gltf", "[1, 2]")); }), {"arr.gltf: the JSON is array, not an object"});
  expect_contains(input_error_of([&] { load_scene(dir.write("obj.gltf", "{}")); }), {"obj.gltf: no \"asset\""});
  // A version other than 2.x, or none, gave assimp's "No suitable reader found".
  std::string v3 = triangle_gltf(R"("scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}])");
  v3.replace(v3.find(R"("2.0")"), 5, R"("3.0")");
  expect_contains(input_error_of([&] { load_scene(dir.write("v3.gltf", v3)); }),
                  {"v3.gltf: asset.version is \"3.0\", not 2.x (rayscout reads glTF 2.0)"});
  expect_contains(input_error_of([&] { load_scene(dir.write("nov.gltf", R"({"asset": {"generator": "x"}})")); }),
                  {"nov.gltf: asset.version is missing or not a string (glTF requires it)"});
  // Nesting that would overflow assimp's recursive parser (it crashed on 200000 levels).
  const std::string deep = triangle_gltf(R"("scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}], "extras": )" +
                                         std::string(300, '[') + std::string(300, ']'));
  expect_contains(input_error_of([&] { load_scene(dir.write("deep.gltf", deep)); }),
                  {"deep.gltf: JSON nested deeper than 256 arrays and objects at line 1"});
  // A well-formed file assimp rejects: its message, marked as assimp's.
  const std::string no_faces = R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {}}]}]})";
  expect_contains(input_error_of([&] { load_scene(dir.write("d.gltf", no_faces)); }), {"d.gltf: assimp cannot read it: "});
}

// Found by fuzzing: nodes reached by two paths (40 nodes each listing the next twice took
// minutes and gigabytes inside assimp), and faces assimp drops for out-of-range indices.
TEST(GltfReader, NodesOutsideATreeAndOutOfRangeIndicesAreErrors) {
  TempDir dir;
  const std::string twice = triangle_gltf(R"("scenes": [{"nodes": [0]}], "nodes": [{"children": [1, 1]}, {"mesh": 0}])");
  testing::expect_contains(testing::input_error_of([&] { load_scene(dir.write("twice.gltf", twice)); }),
                           {"twice.gltf: nodes[0] lists nodes[1] twice as a child"});
  const std::string two_parents = triangle_gltf(
      R"("scenes": [{"nodes": [0]}], "nodes": [{"children": [1, 2]}, {"children": [3]}, {"children": [3]}, {"mesh": 0}])");
  testing::expect_contains(testing::input_error_of([&] { load_scene(dir.write("dag.gltf", two_parents)); }),
                           {"dag.gltf: nodes[3] is a child of nodes[1] and of nodes[2]: glTF nodes form a tree"});
  // A root listed twice, or a root that is also a child, was placed twice by assimp (two
  // copies of every triangle, silently).
  const std::string root_twice = triangle_gltf(R"("scenes": [{"nodes": [0, 0]}], "nodes": [{"mesh": 0}])");
  testing::expect_contains(testing::input_error_of([&] { load_scene(dir.write("roots.gltf", root_twice)); }),
                           {"roots.gltf: scenes[0] lists nodes[0] twice as a root"});
  const std::string root_child = triangle_gltf(R"("scenes": [{"nodes": [0, 1]}], "nodes": [{"children": [1]}, {"mesh": 0}])");
  testing::expect_contains(testing::input_error_of([&] { load_scene(dir.write("rc.gltf", root_child)); }),
                           {"rc.gltf: scenes[0] lists nodes[1] as a root, but it is a child of nodes[0]: glTF nodes form a tree"});
  // A child or root index one past the last node is assimp's to refuse, not a parent slot of
  // the tree check (which has one per node).
  for (const char* members : {R"("scenes": [{"nodes": [0]}], "nodes": [{"children": [2]}, {"mesh": 0}])",
                              R"("scenes": [{"nodes": [0, 2]}], "nodes": [{"children": [1]}, {"mesh": 0}])"}) {
    const std::string msg = testing::input_error_of([&] { load_scene(dir.write("past.gltf", triangle_gltf(members))); });
    testing::expect_contains(msg, {"past.gltf: assimp cannot read it: "});
    EXPECT_EQ(msg.find("nodes form a tree"), std::string::npos) << msg;
  }
  // A node may be a root of several scenes.
  EXPECT_EQ(load_scene(dir.write("scenes.gltf", triangle_gltf(R"("scenes": [{"nodes": [0]}, {"nodes": [0]}], "nodes": [{"mesh": 0}])")))
                .triangles.size(),
            1u);
  // Four vertices, faces (0 1 2) and (1 3 last): last = 9 reaches past the vertex count.
  const auto two_faces = [](uint16_t last) {
    std::string buf;
    for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f, 1.f, 1.f, 0.f}) put<float>(buf, f, false);
    for (uint16_t i : {uint16_t(0), uint16_t(1), uint16_t(2), uint16_t(1), uint16_t(3), last}) put<uint16_t>(buf, i, false);
    return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
      "buffers": [{"byteLength": 60, "uri": "data:application/octet-stream;base64,)" + base64(buf) + R"("}],
      "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0,0,0], "max": [1,1,0]},
                    {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}]})";
  };
  testing::expect_contains(testing::input_error_of([&] { load_scene(dir.write("oob.gltf", two_faces(9))); }),
                           {"oob.gltf: a primitive's indices reach past its vertex count"});
  EXPECT_EQ(load_scene(dir.write("ok.gltf", two_faces(2))).triangles.size(), 2u);
}

// Found by fuzzing: a 52-byte .glb whose JSON chunk declares 4 GB. assimp allocated the
// declared length before reading (4 GB and half a minute); now refused before assimp sees it.
TEST(GltfReader, JsonChunkLongerThanTheFileIsRefusedBeforeAssimpReadsIt) {
  TempDir dir;
  std::string glb;
  put<uint32_t>(glb, 0x46546C67u, false);  // "glTF"
  put<uint32_t>(glb, 2, false);
  put<uint32_t>(glb, 52, false);
  put<uint32_t>(glb, 0xF0000000u, false);  // JSON chunk length
  put<uint32_t>(glb, 0x4E4F534Au, false);  // "JSON"
  glb += R"({"asset": {"version": "2.0"}}   )";
  testing::expect_contains(testing::input_error_of([&] { load_scene(dir.write("big.glb", glb)); }),
                           {"big.glb: truncated: the JSON chunk declares 4026531840 bytes, the file has 32 after the chunk header"});
}

// Node transforms compose down the hierarchy, an instanced mesh appears once per node, and a
// node whose global transform mirrors (determinant < 0) reverses the winding, as glTF 2.0
// specifies, so the face still points +z: corners 0, 2, 1 after the mirror.
TEST(GltfReader, MirroredNodeKeepsItsFrontAndTransformsCompose) {
  TempDir dir;
  const std::string gltf = triangle_gltf(R"("scenes": [{"nodes": [0, 2]}],
    "nodes": [{"translation": [0, 0, 5], "children": [1]}, {"mesh": 0, "scale": [-1, 1, 1]}, {"mesh": 0}])");
  const Scene s = load_scene(dir.write("m.gltf", gltf));
  ASSERT_EQ(s.triangles.size(), 2u);
  const bool first_mirrored = s.triangles[0].v0.z == 5.0f;
  const Triangle& mirrored = s.triangles[first_mirrored ? 0 : 1];
  const Triangle& plain = s.triangles[first_mirrored ? 1 : 0];
  expect_triangle(mirrored, {0, 0, 5}, {0, 1, 5}, {-1, 0, 5});
  expect_triangle(plain, {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  for (const Triangle* t : {&mirrored, &plain}) EXPECT_GT(t->normal().z, 0.0f);
}

TEST(GltfReader, BinaryGlbWithItsBufferInTheBinChunkLoads) {
  TempDir dir;
  std::string bin;
  for (float f : {0.f, 0.f, 0.f, 2.f, 0.f, 0.f, 2.f, 2.f, 0.f, 0.f, 2.f, 0.f}) put<float>(bin, f, false);
  for (uint16_t i : {0, 1, 2, 0, 2, 3}) put<uint16_t>(bin, i, false);
  std::string json = R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
    "buffers": [{"byteLength": 60}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0,0,0], "max": [2,2,0]},
                  {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}]})";
  while (json.size() % 4) json += ' ';
  while (bin.size() % 4) bin += '\0';
  std::string glb;
  put<uint32_t>(glb, 0x46546C67u, false);  // "glTF"
  put<uint32_t>(glb, 2, false);
  put<uint32_t>(glb, uint32_t(12 + 8 + json.size() + 8 + bin.size()), false);
  put<uint32_t>(glb, uint32_t(json.size()), false);
  put<uint32_t>(glb, 0x4E4F534Au, false);  // "JSON"
  glb += json;
  put<uint32_t>(glb, uint32_t(bin.size()), false);
  put<uint32_t>(glb, 0x004E4942u, false);  // "BIN"
  glb += bin;
  const Scene s = load_scene(dir.write("q.glb", glb));
  ASSERT_EQ(s.triangles.size(), 2u);
  expect_triangle(s.triangles[0], {0, 0, 0}, {2, 0, 0}, {2, 2, 0});
  expect_triangle(s.triangles[1], {0, 0, 0}, {2, 2, 0}, {0, 2, 0});
}

}  // namespace
}  // namespace rayscout
