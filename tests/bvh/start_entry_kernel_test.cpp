// The grouped box test of a seeded traversal's start entries (intersect_nodes, 16 lanes with
// AVX-512, 8 with AVX2, scalar otherwise) against the scalar intersect_box_robust: the same
// hit bit and the bit-identical entry distance in every lane, and no bit beyond the group.
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cstring>
#include <random>
#include <vector>

#include "box_test.h"  // private: src/bvh

namespace rayscout {
namespace {

TEST(StartEntryKernel, MatchesTheScalarBoxTestInEveryLane) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  // Boxes around the unit cube; one in eight is flat along an axis, so that axis-parallel rays
  // starting on its plane meet 0 * inf = NaN slab distances.
  std::vector<Bvh2Node> nodes(64);
  for (Bvh2Node& n : nodes) {
    const Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng));
    n.bounds = Bounds3{min(a, b), max(a, b)};
    if (rng() % 8 == 0) n.bounds.hi.y = n.bounds.lo.y = 0.25f;
    n.first = uint32_t(rng());  // not read by the test: garbage must not matter
    n.count = uint16_t(rng());
  }
  constexpr int kLanes = detail::kNodeGroup;
  std::array<int, kLanes> hits{}, misses{};
  for (int trial = 0; trial < 20000; ++trial) {
    const int n = trial % 2 ? kLanes : 1 + trial / 2 % kLanes;  // full groups, and every shorter one
    std::array<uint32_t, kLanes> ids{};
    for (int k = 0; k < n; ++k) ids[size_t(k)] = uint32_t(rng() % nodes.size());
    Vec3 org(2 * u(rng), 2 * u(rng), 2 * u(rng)), dir(u(rng), u(rng), u(rng));
    if (trial % 3 == 1) dir = nodes[ids[size_t(rng()) % size_t(n)]].bounds.center() - org;  // aimed at a box
    if (trial % 5 == 0) { dir = Vec3(0.0f, u(rng) < 0 ? -1.0f : 1.0f, 0.0f); }       // inv_dir x, z = inf
    if (trial % 10 == 0) { dir = Vec3(u(rng), 0.0f, u(rng)); org.y = 0.25f; }        // on the flat boxes' plane
    if (trial % 3 == 0) dir = -dir;                                                  // -inf inverse components
    const RayPrecomp rp(dir);
    const float tmin = trial % 7 == 0 ? -0.5f : 0.0f;  // CullInterval widens tmin below 0
    const float tmax = trial % 4 == 0 ? kInfinity : 3.0f * (u(rng) + 1.0f);
    float dist[kLanes];
    const uint32_t mask = detail::intersect_nodes(nodes.data(), ids.data(), n, org, rp.inv_dir, tmin, tmax, dist);
    EXPECT_EQ(mask >> n, 0u) << "a lane beyond the group reported a hit";
    for (int k = 0; k < n; ++k) {
      float d;
      const bool hit = detail::intersect_box_robust(org, rp.inv_dir, nodes[ids[size_t(k)]].bounds, tmin, tmax, d);
      ASSERT_EQ(hit, (mask >> k & 1u) != 0) << "trial " << trial << " lane " << k;
      uint32_t a, b;
      std::memcpy(&a, &d, 4);
      std::memcpy(&b, &dist[k], 4);
      ASSERT_EQ(a, b) << "entry distance, trial " << trial << " lane " << k << ": " << d << " vs " << dist[k];
      ++(hit ? hits : misses)[size_t(k)];
    }
  }
  // Every lane must have been compared on hits and on misses.
  for (int k = 0; k < kLanes; ++k) {
    EXPECT_GT(hits[size_t(k)], 200) << "lane " << k;
    EXPECT_GT(misses[size_t(k)], 200) << "lane " << k;
  }
}

}  // namespace
}  // namespace rayscout
