// The SIMD block test (4 lanes, and 8 over two adjacent blocks) against core's scalar
// watertight test: same hits, bit-identical t, u, v, and zero edges sent to the fallback.
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <random>

#include "triangle_block_test.h"  // private: src/bvh

namespace rayscout {
namespace {

using Blocks = std::array<TriangleBlock, 2>;

// Two adjacent blocks (the layout WideBvh::leaf_blocks has) of random triangles around the
// unit cube: every second one shares an edge with the one before it, and one in eight is
// degenerate (a repeated vertex, det == 0).
Blocks random_blocks(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  auto point = [&] { return Vec3(u(rng), u(rng), u(rng)); };
  Blocks blocks;
  Triangle prev{point(), point(), point()};
  for (int s = 0; s < 8; ++s) {
    Triangle t = s % 2 ? Triangle{prev.v1, prev.v0, point()} : Triangle{point(), point(), point()};
    if (rng() % 8 == 0) t.v2 = t.v1;
    blocks[size_t(s / 4)].set(s % 4, t);
    prev = t;
  }
  return blocks;
}

struct Tally {
  std::array<int, 8> hits{};
  int fallbacks = 0;
};

// One block test of `lanes` over the blocks starting at `first`, checked against
// intersect_triangle lane by lane.
void check_lanes(const TriangleBlock* first, uint32_t lanes, const Ray& ray, Tally& tally) {
  const RayPrecomp rp(ray.dir);
  detail::BlockHits bh;
  detail::intersect_block(first, lanes, detail::BlockRay<detail::BlockTestLanes>(ray.org, rp), ray.tmin, ray.tmax,
                          bh);
  EXPECT_EQ((bh.hit | bh.fallback) & ~lanes, 0u) << "lanes outside the mask reported";
  EXPECT_EQ(bh.hit & bh.fallback, 0u);
  tally.fallbacks += std::popcount(bh.fallback);
  for (uint32_t l = 0; l < detail::kBlockTestLanes; ++l) {
    if (!(lanes >> l & 1u) || (bh.fallback >> l & 1u)) continue;
    float t, u, v;
    const bool hit = intersect_triangle(ray.org, rp, first[l / 4].get(int(l % 4)), ray.tmin, ray.tmax, t, u, v);
    EXPECT_EQ(hit, (bh.hit >> l & 1u) != 0) << "lane " << l;
    if (!hit || !(bh.hit >> l & 1u)) continue;
    ++tally.hits[l];
    EXPECT_EQ(t, bh.t[l]) << "lane " << l;
    EXPECT_EQ(u, bh.ev[l] / bh.det[l]) << "lane " << l;
    EXPECT_EQ(v, bh.ew[l] / bh.det[l]) << "lane " << l;
  }
}

TEST(TriangleBlockKernel, MatchesTheScalarTestInEveryLaneWidth) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Tally tally;
  for (int trial = 0; trial < 6000; ++trial) {
    const Blocks blocks = random_blocks(rng);
    Ray ray;
    ray.org = Vec3(3 * u(rng), 3 * u(rng), 3 * u(rng));
    // Aimed at a triangle's centre or exactly at a vertex (edge functions 0: the fallback),
    // some along a coordinate axis (infinite inverse direction, zero shear).
    const Triangle target = blocks[rng() % 2].get(int(rng() % 4));
    switch (trial % 4) {
      case 0: ray.dir = target.v0 - ray.org; break;
      case 1: ray.dir = Vec3(u(rng), u(rng), u(rng)); break;
      case 2: ray.dir = Vec3(0.0f, 0.0f, u(rng) < 0 ? -1.0f : 1.0f); ray.org.z = 3.0f * ray.dir.z * -1.0f; break;
      default: ray.dir = (target.v0 + target.v1 + target.v2) * (1.0f / 3.0f) - ray.org; break;
    }
    if (trial % 5 == 0) ray.tmax = 1.0f;     // t exactly 1 at an aimed vertex
    if (trial % 7 == 0) ray.tmin = 0.999f;
    // One block in four lanes and both blocks from every start lane; with four lanes only
    // (portable build) the second block is tested on its own.
    const uint32_t masks[] = {0x1, 0x6, 0xF, 0xF0, 0xFF, 0xF8, 0x3C, 0x70};
    for (const uint32_t m : masks) {
      if (detail::kBlockTestLanes == 8) {
        check_lanes(blocks.data(), m, ray, tally);
      } else {
        if (m & 0xF) check_lanes(&blocks[0], m & 0xF, ray, tally);
        if (m >> 4) check_lanes(&blocks[1], m >> 4, ray, tally);
      }
    }
  }
  // The comparison must have compared something in every lane it can use.
  for (uint32_t l = 0; l < detail::kBlockTestLanes; ++l) EXPECT_GT(tally.hits[l], 100) << "lane " << l;
  EXPECT_GT(tally.fallbacks, 100) << "vertex-aimed rays must exercise the fallback lanes";
}

}  // namespace
}  // namespace rayscout
