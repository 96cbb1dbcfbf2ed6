// The SIMD block test (4 lanes, and 8 over two adjacent blocks) against core's scalar
// watertight test: same hits, bit-identical t, u, v, and zero edges sent to the fallback.
#include <gtest/gtest.h>

#include <array>
#include <random>

#include "../../src/bvh/triangle_block_test.h"

namespace rayscout {
namespace {

// Two adjacent blocks (the layout WideBvh::leaf_blocks has) of random triangles around the
// unit cube; every second triangle shares an edge with the one before it.
std::array<TriangleBlock, 2> random_blocks(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  auto point = [&] { return Vec3(u(rng), u(rng), u(rng)); };
  std::array<TriangleBlock, 2> blocks;
  Triangle prev{point(), point(), point()};
  for (int s = 0; s < 8; ++s) {
    const Triangle t = s % 2 ? Triangle{prev.v1, prev.v0, point()} : Triangle{point(), point(), point()};
    blocks[s / 4].set(s % 4, t);
    prev = t;
  }
  return blocks;
}

// Checks one block test of `lanes` against intersect_triangle lane by lane; returns how many
// lanes went to the fallback.
int check_lanes(const std::array<TriangleBlock, 2>& blocks, uint32_t lanes, const Ray& ray) {
  const RayPrecomp rp(ray.dir);
  detail::BlockHits bh;
  detail::intersect_block(blocks.data(), lanes, detail::BlockRay<detail::BlockTestLanes>(ray.org, rp), ray.tmin,
                          ray.tmax, bh);
  EXPECT_EQ((bh.hit | bh.fallback) & ~lanes, 0u) << "lanes outside the mask reported";
  EXPECT_EQ(bh.hit & bh.fallback, 0u);
  for (uint32_t l = 0; l < detail::kBlockTestLanes; ++l) {
    if (!(lanes >> l & 1u) || (bh.fallback >> l & 1u)) continue;
    float t, u, v;
    const bool hit = intersect_triangle(ray.org, rp, blocks[l / 4].get(int(l % 4)), ray.tmin, ray.tmax, t, u, v);
    EXPECT_EQ(hit, (bh.hit >> l & 1u) != 0) << "lane " << l;
    if (!hit || !(bh.hit >> l & 1u)) continue;
    EXPECT_EQ(t, bh.t[l]) << "lane " << l;
    EXPECT_EQ(u, bh.ev[l] / bh.det[l]) << "lane " << l;
    EXPECT_EQ(v, bh.ew[l] / bh.det[l]) << "lane " << l;
  }
  return std::popcount(bh.fallback);
}

TEST(TriangleBlockKernel, MatchesTheScalarTestInEveryLaneWidth) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  int hits = 0, fallbacks = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const auto blocks = random_blocks(rng);
    Ray ray;
    ray.org = Vec3(3 * u(rng), 3 * u(rng), 3 * u(rng));
    // Every third ray is aimed exactly at a vertex (edge functions 0: the fallback path).
    const Triangle target = blocks[trial % 2].get(trial % 4);
    ray.dir = trial % 3 == 0 ? target.v0 - ray.org : Vec3(u(rng), u(rng), u(rng));
    ray.tmax = trial % 5 == 0 ? 1.5f : kInfinity;
    // One block in four lanes, each block alone, and both blocks from every start lane.
    const uint32_t masks[] = {0x1, 0x6, 0xF, 0xF0, 0xFF, 0xF8, 0x3C, 0x70};
    for (const uint32_t m : masks) {
      if (m > 0xF && detail::kBlockTestLanes == 4) {
        fallbacks += check_lanes(blocks, m & 0xF, ray);  // the portable build tests one block
        continue;
      }
      fallbacks += check_lanes(blocks, m, ray);
    }
    const RayPrecomp rp(ray.dir);
    float t, uu, vv;
    hits += intersect_triangle(ray.org, rp, blocks[0].get(0), ray.tmin, ray.tmax, t, uu, vv);
  }
  EXPECT_GT(hits, 200) << "the rays must hit often enough for the comparison to mean something";
  EXPECT_GT(fallbacks, 100) << "vertex-aimed rays must exercise the fallback lanes";
}

}  // namespace
}  // namespace rayscout
