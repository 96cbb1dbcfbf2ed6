// make_workload: sizes, ordering, determinism and ray validity of the papers' ray sets.
#include <gtest/gtest.h>

#include <cmath>

#include "generated_scenes.h"
#include "rayscout/accelerators.h"
#include "rayscout/core/input_error.h"
#include "rayscout/render/surface.h"
#include "rayscout/render/workloads.h"
#include "rayscout/scene/load_scene.h"

namespace rayscout {
namespace {

bool same_batch(const RayBatch& a, const RayBatch& b) {
  return a.ox == b.ox && a.oy == b.oy && a.oz == b.oz && a.tmin == b.tmin && a.dx == b.dx && a.dy == b.dy &&
         a.dz == b.dz && a.tmax == b.tmax;
}

TEST(Workloads, PrimaryCountAndUnitDirections) {
  const Scene scene = default_scene();
  const auto accel = make_accelerator("brute", scene);
  const RayBatch rays = make_workload(scene, *accel, Workload::Primary, {.width = 16, .height = 12, .spp = 3});
  ASSERT_EQ(rays.size(), 16u * 12u * 3u);
  for (size_t i = 0; i < rays.size(); ++i) {
    EXPECT_NEAR(length(rays[i].dir), 1.0f, 1e-5f);
    EXPECT_EQ(rays[i].org, scene.camera.eye);  // pinhole
  }
}

TEST(Workloads, SecondaryRaysStartAtPrimaryHitsAndAreDeterministic) {
  const Scene scene = default_scene();
  const auto accel = make_accelerator("brute", scene);
  const WorkloadConfig cfg{.width = 20, .height = 20, .spp = 2, .seed = 7};
  const RayBatch primary = make_workload(scene, *accel, Workload::Primary, cfg);
  HitBatch hits;
  accel->intersect(primary, hits);
  size_t n_hits = 0;
  for (size_t i = 0; i < hits.size(); ++i) n_hits += hits.prim[i] != kInvalidId;
  ASSERT_GT(n_hits, 0u);
  for (Workload w : {Workload::Shadow, Workload::Ao, Workload::Diffuse}) {
    const RayBatch a = make_workload(scene, *accel, w, cfg);
    const size_t per_hit = w == Workload::Shadow ? std::max<size_t>(1, scene.point_lights.size()) : 1;
    EXPECT_EQ(a.size(), n_hits * per_hit) << workload_name(w);
    EXPECT_TRUE(same_batch(a, make_workload(scene, *accel, w, cfg))) << workload_name(w);
    WorkloadConfig other = cfg;
    other.seed = 8;
    EXPECT_FALSE(same_batch(a, make_workload(scene, *accel, w, other))) << workload_name(w);
    size_t k = 0;
    for (size_t i = 0; i < hits.size(); ++i) {
      if (hits.prim[i] == kInvalidId) continue;
      const Vec3 p = primary[i].org + primary[i].dir * hits.t[i];
      for (size_t j = 0; j < per_hit; ++j, ++k) EXPECT_LT(length(a[k].org - p), 1e-4f) << workload_name(w);
      if (w == Workload::Ao) {
        EXPECT_GT(a[k - 1].tmax, 0.0f);
      }
      if (w == Workload::Diffuse) {
        EXPECT_EQ(a[k - 1].tmax, kInfinity);
      }
    }
  }
}

TEST(Workloads, ShadowRaysEndBeforeThePointLight) {
  Scene scene = testing::scene_from_triangles(testing::grid(4));
  scene.point_lights = {{Vec3{0.5f, 0.5f, 2.0f}, Vec3{1.0f}}};
  const auto accel = make_accelerator("brute", scene);
  const RayBatch rays = make_workload(scene, *accel, Workload::Shadow, {.width = 8, .height = 8});
  ASSERT_GT(rays.size(), 0u);
  for (size_t i = 0; i < rays.size(); ++i) {
    const Ray r = rays[i];
    const float eps = scene_ray_epsilon(scene.bounds());
    EXPECT_NEAR(length(r.org + r.dir * r.tmax - scene.point_lights[0].position), eps, 1e-5f);
    EXPECT_EQ(r.tmin, 0.0f);
    EXPECT_EQ(r.org.z, eps);  // off the grid (z = 0) by the offset, on the light's side
  }
}

// A floor (normals +z) seen from below: AO and diffuse rays leave on the viewer's side (-z),
// cosine-distributed (E[cos] = 2/3; uniform would give 1/2), AO rays ao_radius long (10 % of
// the diagonal unless configured), diffuse rays unbounded. Each check catches a planted bug
// the test above passes: the geometric normal for the hemisphere, or an AO ray without its end.
TEST(Workloads, AoAndDiffuseRaysAreCosineDistributedOnTheViewersSide) {
  Scene scene = testing::scene_from_triangles(testing::grid(4));
  scene.camera.eye = {0.5f, 0.5f, -1.0f};
  scene.camera.look_at = {0.5f, 0.5f, 0.0f};
  scene.camera.fov_deg = 40;  // the floor fills the view
  const auto accel = make_accelerator("brute", scene);
  const WorkloadConfig cfg{.width = 32, .height = 32, .spp = 1, .seed = 3};
  const float diagonal = length(scene.bounds().diagonal());
  for (const Workload w : {Workload::Ao, Workload::Diffuse}) {
    for (const float radius : {0.0f, 0.25f}) {
      WorkloadConfig c = cfg;
      c.ao_radius = radius;
      const RayBatch rays = make_workload(scene, *accel, w, c);
      ASSERT_EQ(rays.size(), 32u * 32u) << workload_name(w) << ": the camera sees the floor in every pixel";
      double sum_cos = 0;
      for (size_t i = 0; i < rays.size(); ++i) {
        const Ray r = rays[i];
        ASSERT_NEAR(length(r.dir), 1.0f, 1e-5f);
        ASSERT_LT(r.dir.z, 0.0f) << workload_name(w) << " ray " << i << " leaves on the far side of the floor";
        EXPECT_LT(r.org.z, 0.0f) << "offset towards the camera";
        const float want_tmax = w == Workload::Diffuse ? kInfinity : radius > 0 ? radius : 0.1f * diagonal;
        ASSERT_FLOAT_EQ(r.tmax, want_tmax) << workload_name(w) << " ray " << i;
        sum_cos += -r.dir.z;
      }
      // cos theta of a cosine-distributed direction: mean 2/3, sd sqrt(1/2 - 4/9) = 0.236.
      const double se = 0.236 / std::sqrt(double(rays.size()));
      EXPECT_NEAR(sum_cos / double(rays.size()), 2.0 / 3.0, 4 * se) << workload_name(w);
    }
  }
}

// A scene without point or area lights has no shadow rays (it once sampled the empty light
// sampler and wrote past the end of the empty batch: a segmentation fault).
TEST(Workloads, NoLightsNoShadowRays) {
  Scene scene = testing::scene_from_triangles(testing::grid(4));
  scene.point_lights.clear();
  ASSERT_TRUE(scene.emissive_triangles.empty());
  const auto accel = make_accelerator("brute", scene);
  const WorkloadConfig cfg{.width = 8, .height = 8};
  ASSERT_GT(make_workload(scene, *accel, Workload::Ao, cfg).size(), 0u);  // the camera sees the grid
  EXPECT_EQ(make_workload(scene, *accel, Workload::Shadow, cfg).size(), 0u);
}

TEST(Workloads, NamesRoundTripAndAnUnknownNameIsAnInputError) {
  for (Workload w : {Workload::Primary, Workload::Shadow, Workload::Ao, Workload::Diffuse})
    EXPECT_EQ(parse_workload(workload_name(w)), w);
  EXPECT_THROW(parse_workload("bogus"), InputError);
  EXPECT_EQ(workload_names(), (std::vector<std::string>{"primary", "shadow", "ao", "diffuse"}));
}

// More samples than 32-bit ids is an error giving the values (checked before any ray is made).
TEST(Workloads, SampleCountBeyond32BitsNamesTheValues) {
  const Scene scene = default_scene();
  const auto accel = make_accelerator("brute", scene);
  try {
    make_workload(scene, *accel, Workload::Primary, {.width = 65536, .height = 65536, .spp = 1});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("workload: width 65536 x height 65536 x spp 1 = 4294967296 camera samples"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace rayscout

namespace rayscout {
namespace {

// A point light within 2 eps of the hit still gets its shadow ray (a fixed count per hit), one
// that tests nothing: tmax < tmin. Its end dropped (tmax = inf along the normal) passed the
// other tests, and would test the whole scene above the point.
TEST(Workloads, ALightAtTheHitPointGetsARayThatTestsNothing) {
  Scene scene = testing::scene_from_triangles(testing::grid(4));
  scene.camera.eye = {0.5f, 0.5f, 1.0f};
  scene.camera.look_at = {0.5f, 0.5f, 0.0f};
  scene.camera.fov_deg = 1e-3f;  // the one pixel sees (0.5, 0.5, 0), where the light is
  scene.point_lights = {{Vec3{0.5f, 0.5f, 0.0f}, Vec3{1.0f}}};
  const auto accel = make_accelerator("brute", scene);
  const RayBatch rays = make_workload(scene, *accel, Workload::Shadow, {.width = 1, .height = 1});
  ASSERT_EQ(rays.size(), 1u);
  EXPECT_LT(rays[0].tmax, rays[0].tmin);
  std::vector<uint8_t> occ;
  accel->occluded(rays, occ);
  EXPECT_EQ(occ[0], 0);
}

}  // namespace
}  // namespace rayscout
