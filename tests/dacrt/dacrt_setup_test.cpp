// DACRT's SIMD ray setup gives exactly the scalar RayPrecomp constants and records.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "ray_setup.h"  // private: src/dacrt

namespace rayscout {
namespace {

TEST(DacrtSetup, SimdSetupEqualsScalarBitForBit) {
  // Directions with zero, negative zero, tied and huge/tiny components, then random ones.
  const float z = 0.0f, nz = -0.0f, inf = std::numeric_limits<float>::infinity();
  std::vector<Vec3> dirs = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}, {0, -1, 0}, {0, 0, -1},
                            {nz, 1, z}, {1, 1, 1}, {-1, -1, -1}, {1, -1, 1}, {-1, 1, -1}, {1, 1, 0},
                            {0, -1, -1}, {-1, 0, 1}, {1e-30f, -1e-30f, 1e-30f}, {3e38f, 1, -3e38f},
                            {0.5f, -0.5f, 0.25f}, {nz, nz, -1}, {1, nz, nz}, {inf, 1, 0}};
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  while (dirs.size() < 1000) dirs.push_back({u(rng), u(rng), u(rng)});
  RayBatch rays;
  for (size_t i = 0; i < dirs.size(); ++i) {
    rays.ox.push_back(u(rng) * 100.0f); rays.oy.push_back(-u(rng)); rays.oz.push_back(i == 37 ? -500.0f : u(rng));
    rays.tmin.push_back(0.0f); rays.tmax.push_back(i % 3 ? inf : float(i));
    rays.dx.push_back(dirs[i].x); rays.dy.push_back(dirs[i].y); rays.dz.push_back(dirs[i].z);
  }
  const size_t n = rays.size();
  // Non-finite origin coordinates (rays that miss) in a SIMD block and in the scalar tail do
  // not count towards the magnitude (the box padding).
  rays.ox[40] = inf; rays.oy[41] = -inf; rays.oz[42] = std::numeric_limits<float>::quiet_NaN(); rays.ox[n - 1] = -inf;
  std::vector<dacrt::RayRecord> rec(n), rec_ref(n);
  std::vector<dacrt::RayShear> sh(n), sh_ref(n);
  std::vector<uint32_t> rid(n);
  // Start at 3 so the SIMD blocks are not aligned with the batch.
  const float m = dacrt::setup_rays(rays, 3, n, rec.data(), sh.data(), rid.data());
  float m_ref = 0.0f;
  for (size_t i = 3; i < n; ++i) {
    dacrt::setup_ray(rays, i, rec_ref.data(), sh_ref.data());
    for (const float o : {rays.ox[i], rays.oy[i], rays.oz[i]})
      if (std::isfinite(o)) m_ref = std::max(m_ref, std::fabs(o));
    ASSERT_EQ(rid[i], i);
    const auto* a = reinterpret_cast<const uint32_t*>(&rec[i]);
    const auto* b = reinterpret_cast<const uint32_t*>(&rec_ref[i]);
    for (int f = 0; f < 8; ++f) ASSERT_EQ(a[f], b[f]) << "ray " << i << " record field " << f;
    const auto* c = reinterpret_cast<const uint32_t*>(&sh[i]);
    const auto* d = reinterpret_cast<const uint32_t*>(&sh_ref[i]);
    for (int f = 0; f < 4; ++f) ASSERT_EQ(c[f], d[f]) << "ray " << i << " shear field " << f;
    const RayPrecomp p(dirs[i]), q = to_precomp(sh[i]);
    EXPECT_EQ(p.kx, q.kx); EXPECT_EQ(p.ky, q.ky); EXPECT_EQ(p.kz, q.kz);
  }
  EXPECT_EQ(m, m_ref);
  EXPECT_EQ(m, 500.0f);
}

}  // namespace
}  // namespace rayscout
