// VoxelSurfaces: surface origins of sample rays lie on the triangles inside their voxel,
// uniformly by area.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "rayscout/shafts/shaft_grid.h"
#include "voxel_surfaces.h"

namespace rayscout {
namespace {

// A slanted triangle that crosses many voxels of a 4 x 4 x 4 grid, and a small one inside a
// single voxel: every point lies in its voxel and on a triangle, and a voxel without surface
// has no point.
TEST(VoxelSurfaces, PointsLieOnTheTrianglesInsideTheirVoxel) {
  const Triangle big{{0.1f, 0.2f, 0.0f}, {4.0f, 0.5f, 3.9f}, {0.3f, 4.0f, 2.2f}};
  const Triangle small{{3.1f, 0.2f, 0.3f}, {3.6f, 0.4f, 0.5f}, {3.3f, 0.8f, 0.2f}};
  const std::vector<Triangle> tris{big, small};
  const ShaftGrid grid(Bounds3{{0, 0, 0}, {4, 4, 4}}, {4, 4, 4}, 2);
  std::vector<uint32_t> all(grid.voxel_count());
  for (uint32_t v = 0; v < all.size(); ++v) all[v] = v;
  const detail::VoxelSurfaces surfaces(grid, tris, all);
  auto on_triangle = [](const Triangle& t, const Vec3& p) {
    const Vec3 n = normalize(t.normal());
    if (std::fabs(dot(n, p - t.v0)) > 1e-5f) return false;
    // Inside: p is on the inner side of each edge (within rounding).
    const Vec3 e[3] = {t.v1 - t.v0, t.v2 - t.v1, t.v0 - t.v2}, v[3] = {t.v0, t.v1, t.v2};
    for (int i = 0; i < 3; ++i)
      if (dot(cross(e[i], p - v[i]), n) < -1e-5f) return false;
    return true;
  };
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 0.99999994f);
  int with_surface = 0;
  for (uint32_t v = 0; v < grid.voxel_count(); ++v) {
    const Bounds3 box = grid.voxel_box(v);
    Vec3 p;
    const float first[3] = {0.5f, 0.5f, 0.5f};
    if (!surfaces.sample(v, first, p)) continue;
    ++with_surface;
    for (int i = 0; i < 200; ++i) {
      const float rnd[3] = {u(rng), u(rng), u(rng)};
      ASSERT_TRUE(surfaces.sample(v, rnd, p));
      for (int a = 0; a < 3; ++a) {
        EXPECT_GE(p[a], box.lo[a] - 1e-5f) << "voxel " << v;
        EXPECT_LE(p[a], box.hi[a] + 1e-5f) << "voxel " << v;
      }
      EXPECT_TRUE(on_triangle(big, p) || on_triangle(small, p)) << "voxel " << v;
    }
  }
  // The big triangle crosses a slab of voxels, not all 64 and not just a few.
  EXPECT_GT(with_surface, 10);
  EXPECT_LT(with_surface, 50);
  // Voxels outside the constructor's set have no surface.
  const std::vector<uint32_t> one{grid.voxel_id(3, 0, 0)};
  const detail::VoxelSurfaces only(grid, tris, one);
  Vec3 p;
  const float rnd[3] = {0.3f, 0.3f, 0.3f};
  EXPECT_TRUE(only.sample(grid.voxel_id(3, 0, 0), rnd, p));
  EXPECT_FALSE(only.sample(grid.voxel_id(0, 0, 0), rnd, p));
  EXPECT_GT(surfaces.epsilon(), 0.0f);
}

// A floor square through a 3 x 1 x 2 grid, split into two triangles along its diagonal, which
// cuts most voxels into pieces of unequal area: in each voxel the points cover the voxel's part
// of the floor uniformly (mean at its centre, each half of it getting half the points).
TEST(VoxelSurfaces, PointsAreUniformByArea) {
  const Vec3 a{0, 0.5f, 0}, b{2, 0.5f, 0}, c{2, 0.5f, 2}, d{0, 0.5f, 2};
  const std::vector<Triangle> tris{{a, b, c}, {a, c, d}};
  const ShaftGrid grid(Bounds3{{0, 0, 0}, {2, 1, 2}}, {3, 1, 2}, 1);
  const std::vector<uint32_t> voxels{0, 1, 2, 3, 4, 5};
  const detail::VoxelSurfaces surfaces(grid, tris, voxels);
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(0.0f, 0.99999994f);
  for (uint32_t v : voxels) {
    const Bounds3 box = grid.voxel_box(v);
    const int n = 20000;
    double mx = 0, mz = 0;
    int left = 0;
    for (int i = 0; i < n; ++i) {
      const float rnd[3] = {u(rng), u(rng), u(rng)};
      Vec3 p;
      ASSERT_TRUE(surfaces.sample(v, rnd, p));
      EXPECT_NEAR(p.y, 0.5f, 1e-6f);
      mx += p.x;
      mz += p.z;
      left += p.x < 0.5f * (box.lo.x + box.hi.x) ? 1 : 0;
    }
    // Standard error of the mean over 20000 points: below 0.002.
    EXPECT_NEAR(mx / n, 0.5 * (box.lo.x + box.hi.x), 0.01) << "voxel " << v;
    EXPECT_NEAR(mz / n, 0.5 * (box.lo.z + box.hi.z), 0.01) << "voxel " << v;
    EXPECT_NEAR(double(left) / n, 0.5, 0.02) << "voxel " << v;
  }
}

}  // namespace
}  // namespace rayscout
