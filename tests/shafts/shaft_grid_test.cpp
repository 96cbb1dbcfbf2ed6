// ShaftGrid: resolution from a voxel count, classification inside, outside and on borders.
#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "rayscout/shafts/shaft_grid.h"
#include "shaft.h"

namespace rayscout {
namespace {

TEST(ShaftGrid, CubicalResolutionFollowsTheBoxShape) {
  const Bounds3 box{{0, 0, 0}, {4, 2, 1}};
  const auto res = ShaftGrid::cubical_resolution(box, 8 * 8 * 8);
  // Voxel side ~ (8 / 512)^(1/3) = 0.25: 16 x 8 x 4.
  EXPECT_EQ(res[0], 16);
  EXPECT_EQ(res[1], 8);
  EXPECT_EQ(res[2], 4);
  const auto flat = ShaftGrid::cubical_resolution(Bounds3{{0, 0, 0}, {1, 1, 0}}, 100);
  EXPECT_EQ(flat[2], 1);
  EXPECT_EQ(flat[0], 10);
}

TEST(ShaftGrid, ClassifiesOriginVoxelAndDirectionCell) {
  const ShaftGrid g(Bounds3{{0, 0, 0}, {4, 4, 4}}, {4, 4, 4}, 2);
  ShaftCoord c;
  ASSERT_TRUE(g.classify(Ray{{1.5f, 2.5f, 3.5f}, 0.0f, {1.0f, 0.5f, -0.5f}, kInfinity}, c));
  EXPECT_EQ(c.voxel, g.voxel_id(1, 2, 3));
  // Face +x (0), u = y / x = 0.5 -> cell 1, v = z / x = -0.5 -> cell 0.
  EXPECT_EQ(c.cell, (0u * 2 + 0) * 2 + 1);
  ASSERT_TRUE(g.classify(Ray{{0.5f, 0.5f, 0.5f}, 0.0f, {0.0f, 0.0f, -2.0f}, kInfinity}, c));
  const auto r = g.cell_range(c.cell);
  EXPECT_EQ(r.axis, 2);
  EXPECT_EQ(r.sign, -1);
}

TEST(ShaftGrid, RejectsRaysItCannotClassifySafely) {
  const ShaftGrid g(Bounds3{{0, 0, 0}, {1, 1, 1}}, {4, 4, 4}, 3);
  ShaftCoord c;
  EXPECT_FALSE(g.classify(Ray{{0.5f, 0.5f, 0.5f}, -1.0f, {1, 0, 0}, kInfinity}, c));   // tmin < 0
  EXPECT_FALSE(g.classify(Ray{{0.5f, 0.5f, 0.5f}, 0.0f, {0, 0, 0}, kInfinity}, c));    // zero dir
  EXPECT_FALSE(g.classify(Ray{{0.5f, 0.5f, NAN}, 0.0f, {1, 0, 0}, kInfinity}, c));     // NaN
  EXPECT_FALSE(g.classify(Ray{{2.0f, 0.5f, 0.5f}, 0.0f, {1, 0, 0}, kInfinity}, c));    // away
  EXPECT_FALSE(g.classify(Ray{{2.0f, 2.0f, 0.5f}, 0.0f, {0, 1, 0}, kInfinity}, c));    // parallel, outside slab
  EXPECT_FALSE(g.classify(Ray{{-100.0f, 0.5f, 0.5f}, 0.0f, {1, 0, 0}, kInfinity}, c)); // too far
  // Largest component subnormal: 1 / it is infinite, and the cell index was int(NaN).
  const float tiny = std::numeric_limits<float>::denorm_min();
  EXPECT_FALSE(g.classify(Ray{{0.5f, 0.5f, 0.5f}, 0.0f, {tiny, 0, tiny}, kInfinity}, c));
  EXPECT_FALSE(g.classify(Ray{{-1.0f, 0.5f, 0.5f}, 0.0f, {tiny, 0, 0}, kInfinity}, c));
}

TEST(ShaftGrid, OutsideOriginsAreClassifiedAtTheirEntryPoint) {
  const ShaftGrid g(Bounds3{{0, 0, 0}, {1, 1, 1}}, {4, 4, 4}, 3);
  ShaftCoord c;
  ASSERT_TRUE(g.classify(Ray{{-1.0f, 0.6f, 0.1f}, 0.0f, {1, 0, 0}, kInfinity}, c));
  EXPECT_EQ(c.voxel, g.voxel_id(0, 2, 0));
  ASSERT_TRUE(g.classify(Ray{{2.0f, 2.0f, 0.9f}, 0.0f, {-1, -1, 0}, kInfinity}, c));
  EXPECT_EQ(c.voxel, g.voxel_id(3, 3, 3));
  // Enters through a corner region from below.
  ASSERT_TRUE(g.classify(Ray{{0.3f, -3.0f, 0.3f}, 0.0f, {0, 1, 0}, kInfinity}, c));
  EXPECT_EQ(c.voxel, g.voxel_id(1, 0, 1));
}

// Every direction, including axis-parallel ones and ones exactly on cube-map face borders,
// lies in the padded cone of the cell it is classified into.
TEST(ShaftGrid, DirectionsLieInTheirCell) {
  for (int d : {1, 2, 3, 5}) {
    const ShaftGrid g(Bounds3{{0, 0, 0}, {1, 1, 1}}, {1, 1, 1}, d);
    std::vector<Vec3> dirs;
    const float vals[] = {-1.0f, -0.5f, 0.0f, 1.0f / 3.0f, 0.5f, 1.0f, 0.2f, -0.6f};
    for (float x : vals)
      for (float y : vals)
        for (float z : vals)
          if (x != 0 || y != 0 || z != 0) dirs.push_back({x, y, z});
    std::mt19937 rng(5);
    std::normal_distribution<float> n;
    for (int i = 0; i < 2000; ++i) dirs.push_back({n(rng), n(rng), n(rng)});
    for (const Vec3& dir : dirs) {
      const auto r = g.cell_range(g.dir_cell(dir));
      const int ua = r.axis == 2 ? 0 : r.axis + 1, va = ua == 2 ? 0 : ua + 1;
      const double m = double(dir[r.axis]) * r.sign;
      ASSERT_GT(m, 0.0) << dir.x << " " << dir.y << " " << dir.z;
      const double u = dir[ua] / m, v = dir[va] / m;
      EXPECT_GE(u, r.u0 - Shaft::kPadDir);
      EXPECT_LE(u, r.u1 + Shaft::kPadDir);
      EXPECT_GE(v, r.v0 - Shaft::kPadDir);
      EXPECT_LE(v, r.v1 + Shaft::kPadDir);
    }
  }
}

TEST(Shaft, OverlapsEveryReachablePointAndCullsTheBackSide) {
  const ShaftGrid g(Bounds3{{0, 0, 0}, {1, 1, 1}}, {5, 4, 3}, 3);
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  size_t culled = 0, tested = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const ShaftCoord coord{uint32_t(rng() % g.voxel_count()), uint32_t(rng() % g.cells_per_voxel())};
    const Shaft shaft(g, coord);
    for (int i = 0; i < 50; ++i) {
      float rnd[5];
      for (float& r : rnd) r = u01(rng);
      const Ray ray = shaft.sample_ray(rnd);
      const Vec3 p = ray.org + ray.dir * (3.0f * u01(rng));
      EXPECT_TRUE(shaft.overlaps(Bounds3{p, p})) << "a reachable point was culled";
      // A random small box anywhere: count culls so the test shows the shaft culls at all.
      const Vec3 q{u01(rng) * 3 - 1, u01(rng) * 3 - 1, u01(rng) * 3 - 1};
      ++tested;
      culled += !shaft.overlaps(Bounds3{q, q + Vec3{0.01f}});
    }
    // Behind the voxel along the face axis: unreachable.
    const auto r = g.cell_range(coord.cell);
    Bounds3 vb = g.voxel_box(coord.voxel), behind = vb;
    if (r.sign > 0) { behind.hi[r.axis] = vb.lo[r.axis] - 0.01f; behind.lo[r.axis] = behind.hi[r.axis] - 0.1f; }
    else { behind.lo[r.axis] = vb.hi[r.axis] + 0.01f; behind.hi[r.axis] = behind.lo[r.axis] + 0.1f; }
    EXPECT_FALSE(shaft.overlaps(behind));
  }
  EXPECT_GT(culled, tested / 2) << "narrow shafts should cull most random boxes";
}

// The other direction: points just outside each of the cone's four sides (directions beyond
// the cell by 5-10 % of its width, far from the voxel) that the exact test culls with a margin
// of 1e-3 of the diagonal are culled by the float test too.
TEST(Shaft, FloatTestCullsWhatTheExactTestCullsBeyondEachSide) {
  const ShaftGrid g(Bounds3{{-3, 0, 1}, {5, 2, 4}}, {6, 3, 4}, 5);
  std::mt19937 rng(37);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  const float margin = 1e-3f * length(g.box().diagonal());
  size_t checked[4] = {};
  for (uint32_t v = 0; v < g.voxel_count(); v += 5)
    for (uint32_t c = 0; c < g.cells_per_voxel(); ++c) {
      const Shaft shaft(g, {v, c});
      const ShaftGrid::CellRange r = shaft.cell();
      const double du = r.u1 - r.u0, dv = r.v1 - r.v0;
      for (int side = 0; side < 4; ++side) {
        ShaftGrid::CellRange out = r;
        if (side == 0) { out.u1 = r.u0 - 0.05 * du; out.u0 = r.u0 - 0.1 * du; }
        if (side == 1) { out.u0 = r.u1 + 0.05 * du; out.u1 = r.u1 + 0.1 * du; }
        if (side == 2) { out.v1 = r.v0 - 0.05 * dv; out.v0 = r.v0 - 0.1 * dv; }
        if (side == 3) { out.v0 = r.v1 + 0.05 * dv; out.v1 = r.v1 + 0.1 * dv; }
        for (int i = 0; i < 4; ++i) {
          const float rnd[5] = {u01(rng), u01(rng), u01(rng), u01(rng), u01(rng)};
          const Ray ray = Shaft::sample_ray(shaft.voxel(), out, rnd);
          const Vec3 p = ray.org + ray.dir * ((20.0f + 20.0f * u01(rng)) / length(ray.dir));
          if (shaft.overlaps_exact(Bounds3{p - Vec3{margin}, p + Vec3{margin}})) continue;
          ++checked[side];
          ASSERT_FALSE(shaft.overlaps(Bounds3{p, p}))
              << "voxel " << v << " cell " << c << " side " << side << ": the float test kept a point "
              << margin << " away from the shaft";
        }
      }
    }
  for (int side = 0; side < 4; ++side) EXPECT_GT(checked[side], 1000u) << "side " << side;
}

// Each side plane of the cone is a bevel plane (neighbouring edges differ in one face
// coordinate), so a shaft has at most 3 face and 12 bevel axes: one 16-slot row of the float
// test. With the sides kept as well, 1613 of 2750 shafts of a review's sample took two rows.
TEST(Shaft, SidePlanesAreNotRepeatedAfterTheBevels) {
  for (int d = 1; d <= 6; ++d) {
    const ShaftGrid g(Bounds3{{-3, 0, 1}, {5, 2, 4}}, {3, 2, 2}, d);
    int most = 0;
    for (uint32_t v = 0; v < g.voxel_count(); ++v)
      for (uint32_t c = 0; c < g.cells_per_voxel(); ++c) most = std::max(most, Shaft(g, {v, c}).axis_count());
    EXPECT_LE(most, 15) << "d = " << d;
    EXPECT_GE(most, 5) << "d = " << d;  // the 4 sides and the back face at least
  }
}

// The float test (used by the build) must keep every box the exact double test keeps, and
// may keep only slightly more: boxes at random and grazing the shaft (shifted by tiny steps
// across its separating planes).
TEST(Shaft, FloatTestKeepsEveryBoxTheExactTestKeeps) {
  const ShaftGrid g(Bounds3{{-120, 3, -40}, {250, 90, 75}}, {9, 4, 6}, 4);
  std::mt19937 rng(31);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  size_t exact_kept = 0, float_kept = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const ShaftCoord coord{uint32_t(rng() % g.voxel_count()), uint32_t(rng() % g.cells_per_voxel())};
    const Shaft shaft(g, coord);
    for (int i = 0; i < 200; ++i) {
      const Vec3 lo = g.box().lo, d = g.box().diagonal();
      const Vec3 q{lo.x + d.x * (1.4f * u01(rng) - 0.2f), lo.y + d.y * (1.4f * u01(rng) - 0.2f),
                   lo.z + d.z * (1.4f * u01(rng) - 0.2f)};
      Bounds3 b{q, q + Vec3{u01(rng), u01(rng), u01(rng)} * (0.05f * max_component(d))};
      // Bisect a shift along a random axis to a box that just touches the shaft.
      const int axis = int(rng() % 3);
      float in = 0.0f, out = 0.0f;
      if (i % 2 && !shaft.overlaps_exact(b)) {
        const float dir = u01(rng) < 0.5f ? -1.0f : 1.0f;
        for (float step = 1.0f; step < 4.0f * max_component(d); step *= 2.0f) {
          Bounds3 m = b;
          m.lo[axis] += dir * step;
          m.hi[axis] += dir * step;
          if (shaft.overlaps_exact(m)) { in = step; break; }
          out = step;
        }
        for (int k = 0; in > 0.0f && k < 40; ++k) {
          const float mid = 0.5f * (in + out);
          Bounds3 m = b;
          m.lo[axis] += dir * mid;
          m.hi[axis] += dir * mid;
          (shaft.overlaps_exact(m) ? in : out) = mid;
        }
        if (in > 0.0f) {
          b.lo[axis] += dir * in;
          b.hi[axis] += dir * in;
        }
      }
      const bool exact = shaft.overlaps_exact(b), fast = shaft.overlaps(b);
      exact_kept += exact;
      float_kept += fast;
      if (exact) {
        EXPECT_TRUE(fast) << "the float test culled a box the exact test keeps";
      }
    }
  }
  EXPECT_GT(exact_kept, 2000u);
  EXPECT_LE(float_kept, exact_kept + exact_kept / 50) << "the float test should be nearly as tight";
}

}  // namespace
}  // namespace rayscout
