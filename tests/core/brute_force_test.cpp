// The brute-force reference on hand-placed triangles with known answers: every accelerator
// is checked against it, so it is checked against arithmetic done by hand.
#include <gtest/gtest.h>

#include <vector>

#include "rayscout/core/accelerator.h"

namespace rayscout {
namespace {

// Right triangles with legs 4 along x and y, in the planes z = 2 (ids 0, 1: the same one
// twice, in the order that puts the larger id first) and z = 5 (id 2), all facing the origin;
// one more at z = 3 far off to the side (id 3).
const std::vector<Triangle> kTriangles = {
    {{0, 0, 2}, {4, 0, 2}, {0, 4, 2}},
    {{0, 0, 2}, {4, 0, 2}, {0, 4, 2}},
    {{0, 0, 5}, {4, 0, 5}, {0, 4, 5}},
    {{100, 100, 3}, {104, 100, 3}, {100, 104, 3}},
};

RayBatch batch(std::initializer_list<Ray> rays) {
  RayBatch b;
  for (const Ray& r : rays) b.push_back(r);
  return b;
}

TEST(BruteForce, ClosestHitsByHand) {
  const BruteForce brute(kTriangles);
  const RayBatch rays = batch({
      {{1, 2, 0}, 0.0f, {0, 0, 1}, kInfinity},     // 0: the coincident pair at t = 2
      {{1, 2, 0}, 2.5f, {0, 0, 1}, kInfinity},     // 1: tmin beyond z = 2: the far one at t = 5
      {{1, 2, 0}, 0.0f, {0, 0, 1}, 1.5f},          // 2: tmax short of everything
      {{1, 2, 0}, 0.0f, {0, 0, -1}, kInfinity},    // 3: pointing away
      {{1, 2, 0}, 0.0f, {0, 0, 0.5f}, kInfinity},  // 4: half-length direction: t doubles
      {{3, 3, 0}, 0.0f, {0, 0, 1}, kInfinity},     // 5: outside the hypotenuse x + y = 4
      {{101, 102, 0}, 0.0f, {0, 0, 1}, kInfinity}, // 6: the one off to the side
  });
  HitBatch hits;
  TraceStats stats;
  brute.intersect(rays, hits, &stats);
  ASSERT_EQ(hits.size(), rays.size());
  // Coincident triangles tie at the same t: the smaller id wins (is_closer).
  EXPECT_EQ(hits.prim[0], 0u);
  EXPECT_EQ(hits.t[0], 2.0f);
  EXPECT_FLOAT_EQ(hits.u[0], 0.25f);  // x = 4u
  EXPECT_FLOAT_EQ(hits.v[0], 0.5f);   // y = 4v
  EXPECT_EQ(hits.prim[1], 2u);
  EXPECT_EQ(hits.t[1], 5.0f);
  EXPECT_EQ(hits.prim[2], kInvalidId);
  EXPECT_EQ(hits.prim[3], kInvalidId);
  EXPECT_EQ(hits.prim[4], 0u);
  EXPECT_EQ(hits.t[4], 4.0f);
  EXPECT_EQ(hits.prim[5], kInvalidId);
  EXPECT_EQ(hits.prim[6], 3u);
  EXPECT_EQ(hits.t[6], 3.0f);
  EXPECT_FLOAT_EQ(hits.u[6], 0.25f);
  EXPECT_FLOAT_EQ(hits.v[6], 0.5f);
  // Every ray against every triangle, and nothing else.
  EXPECT_EQ(stats.rays, rays.size());
  EXPECT_EQ(stats.ray_tri_tests, rays.size() * kTriangles.size());
  EXPECT_EQ(stats.ray_box_tests, 0u);
}

TEST(BruteForce, OcclusionByHand) {
  const BruteForce brute(kTriangles);
  const RayBatch rays = batch({
      {{1, 2, 0}, 0.0f, {0, 0, 1}, 2.0f},        // ends exactly on z = 2: blocked (tmax inclusive)
      {{1, 2, 0}, 0.0f, {0, 0, 1}, 1.999f},      // ends short of it
      {{1, 2, 0}, 2.5f, {0, 0, 1}, 4.5f},        // between the planes
      {{1, 2, 0}, 2.5f, {0, 0, 1}, kInfinity},   // from between the planes to the far one
      {{3, 3, 0}, 0.0f, {0, 0, 1}, kInfinity},   // misses everything
  });
  std::vector<uint8_t> occ;
  brute.occluded(rays, occ);
  EXPECT_EQ(occ, (std::vector<uint8_t>{1, 0, 0, 1, 0}));
}

}  // namespace
}  // namespace rayscout
