// The benchmark scenes load with the triangle counts and bounds of their SOURCE.md.
#include <gtest/gtest.h>

#include <ostream>
#include <string>

#include "rayscout/core/scenes_dir.h"
#include "rayscout/scene/load_scene.h"
#include "rayscout/scene/mesh.h"

namespace rayscout {
namespace {

struct RealScene {
  const char* file;
  size_t faces;     // triangles, n - 2 per polygon, as counted in SOURCE.md
  size_t dropped;   // zero-area faces among them (dropped by the scene, reported in a warning)
  Vec3 lo, hi;      // bounding box from SOURCE.md (printed to ~6 digits)
};
// ctest lists the case by its file, not as "48-byte object <15-42 3A-29 ...>".
void PrintTo(const RealScene& r, std::ostream* os) { *os << r.file; }

class RealScenes : public ::testing::TestWithParam<RealScene> {};

TEST_P(RealScenes, CountsAndBounds) {
  const RealScene& r = GetParam();
  const auto path = find_scene_file(r.file);
  if (!path) GTEST_SKIP() << r.file << " not found under " << scenes_dir() << " (set RAYSCOUT_SCENES)";
  const Mesh mesh = read_mesh(*path);
  EXPECT_EQ(mesh.faces.size(), r.faces);
  const Scene s = load_scene(*path);
  EXPECT_EQ(s.triangles.size(), r.faces - r.dropped);
  if (r.dropped) {
    ASSERT_FALSE(s.warnings.empty());
    EXPECT_NE(s.warnings.back().find("dropped " + std::to_string(r.dropped) + " degenerate"), std::string::npos)
        << s.warnings.back();
  }
  const Bounds3 b = s.bounds();
  const float tol = 1e-4f * std::max(1.0f, max_component(abs(r.hi - r.lo)));
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(b.lo[a], r.lo[a], tol) << "axis " << a;
    EXPECT_NEAR(b.hi[a], r.hi[a], tol) << "axis " << a;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, RealScenes,
    ::testing::Values(
        RealScene{"crytek-sponza/sponza.obj", 262205, 1, {-192.095f, -12.6443f, -118.281f}, {179.991f, 142.943f, 110.543f}},
        RealScene{"sibenik/sibenik.obj", 75284, 9, {-20.1411f, -15.3123f, -8.4968f}, {20.1411f, 15.3f, 8.4968f}},
        RealScene{"conference/conference.obj", 331179, 53627, {-1020.13f, -2.7924f, -1055.66f}, {1685.81f, 650.293f, 668.489f}},
        RealScene{"dabrovic-sponza/sponza.obj", 66454, 1, {-17.4028f, -0.9067f, -7.7985f}, {17.4172f, 15.6533f, 7.8015f}},
        RealScene{"stanford-bunny/bun_zipper.ply", 69451, 0, {-0.0947f, 0.0330f, -0.0619f}, {0.0610f, 0.1873f, 0.0588f}},
        RealScene{"stanford-dragon/dragon_vrip_res2.ply", 202520, 0, {-0.1082f, 0.0527f, -0.0503f}, {0.0964f, 0.1971f, 0.0411f}},
        RealScene{"cornell-box/CornellBox-Original.obj", 36, 0, {-1.02f, 0.0f, -1.04f}, {1.0f, 1.99f, 0.99f}}),
    [](const auto& info) {
      std::string n = info.param.file;
      for (auto& c : n)
        if (!isalnum(static_cast<unsigned char>(c))) c = '_';
      return n;
    });

TEST(RealSceneMaterials, CornellBoxMirror) {
  const auto path = find_scene_file("cornell-box/CornellBox-Mirror.obj");
  if (!path) GTEST_SKIP() << "cornell-box/CornellBox-Mirror.obj not found under " << scenes_dir();
  const Scene s = load_scene(*path);
  EXPECT_EQ(s.triangles.size(), 36u);
  EXPECT_EQ(s.emissive_triangles.size(), 2u);
  bool mirror = false;
  for (const auto& m : s.materials) mirror = mirror || (m.name == "tallBox" && m.type == Material::Type::Mirror);
  EXPECT_TRUE(mirror);
  EXPECT_TRUE(s.warnings.empty());
}

}  // namespace
}  // namespace rayscout
