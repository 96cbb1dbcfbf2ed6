// DACRT's SIMD leaf kernels against the scalar ones (core's intersect_triangle and is_closer):
// the same hits bit for bit and the same test counts, on triangles that make exact ties and
// zero edge functions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <vector>

#include "leaf_avx512.h"  // private: src/dacrt
#include "leaf_kernels.h"

namespace rayscout::dacrt {
namespace {

#if defined(__AVX512F__)
struct LeafCase {
  std::vector<Triangle> tris;
  std::vector<RayRecord> rays;
  std::vector<RayShear> pre;
  std::vector<uint32_t> prim;
  std::vector<float> u, v;
  std::vector<uint8_t> occ;
  HitOut out() { return {prim.data(), u.data(), v.data()}; }
};

// Triangles of a unit grid in z = 0 sharing edges and vertices, each twice (the same
// geometry under two ids: exact t ties), plus random ones; rays through grid vertices
// and edges (zero edge functions) and random rays, some with an earlier hit or tmin > 0.
LeafCase make_case(uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  LeafCase c;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) {
      const Vec3 p00(float(x), float(y), 0.0f), p10(float(x + 1), float(y), 0.0f);
      const Vec3 p01(float(x), float(y + 1), 0.0f), p11(float(x + 1), float(y + 1), 0.0f);
      for (int twice = 0; twice < 2; ++twice) {
        c.tris.push_back({p00, p10, p11});
        c.tris.push_back({p00, p11, p01});
      }
    }
  while (c.tris.size() < 83) {  // not a multiple of 16: a tail group
    const Vec3 a(u01(rng) * 4, u01(rng) * 4, u01(rng) * 2 - 1);
    c.tris.push_back({a, a + Vec3(u01(rng), u01(rng), 0.3f), a + Vec3(-u01(rng), u01(rng), -0.2f)});
  }
  for (int i = 0; i < 7; ++i) {
    Vec3 o(u01(rng) * 4, u01(rng) * 4, 2.0f), d(u01(rng) - 0.5f, u01(rng) - 0.5f, -1.0f);
    if (i % 3 == 0) { o = Vec3(float(i % 4), 1.0f, 2.0f); d = Vec3(0.0f, 0.0f, -1.0f); }          // a grid vertex
    if (i % 3 == 1) { o = Vec3(float(i % 4) + 0.5f, 2.0f, 3.0f); d = Vec3(0.0f, 0.0f, -1.5f); }   // a grid edge
    RayRecord r{o.x, o.y, o.z, 0.0f, 1.0f / d.x, 1.0f / d.y, 1.0f / d.z, kInfinity};
    if (i == 4) r.tmin = 1.0f;
    c.rays.push_back(r);
    c.pre.push_back(shear_of(RayPrecomp(d)));
    c.prim.push_back(kInvalidId);
    c.u.push_back(0.0f);
    c.v.push_back(0.0f);
  }
  // An earlier hit at exactly the distance of the grid with a larger id than the copies'.
  c.rays[3].t = 2.0f;
  c.prim[3] = 40;
  c.occ.assign(c.rays.size(), 0);
  c.occ[5] = 1;  // retired before this leaf
  retire(c.rays[5]);
  return c;
}

std::vector<uint32_t> ids(size_t n, uint32_t seed) {
  std::vector<uint32_t> v(n);
  for (uint32_t i = 0; i < n; ++i) v[i] = i;
  std::shuffle(v.begin(), v.end(), std::mt19937(seed));
  return v;
}

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(DacrtLeafKernels, FewRaysKernelEqualsScalarBitForBit) {
  int hits = 0, blocked = 0;
  for (uint32_t seed = 1; seed <= 20; ++seed) {
    LeafCase want = make_case(seed), got = make_case(seed);
    const std::vector<uint32_t> tid = ids(want.tris.size(), seed), rid = ids(want.rays.size(), seed + 100);
    const uint64_t nw = leaf_intersect(want.rays.data(), want.pre.data(), rid.data(), rid.size(), want.tris.data(),
                                       tid.data(), tid.size(), want.out());
    const uint64_t ng = leaf_few_rays<false>(got.rays.data(), got.pre.data(), rid.data(), rid.size(), got.tris.data(),
                                             tid.data(), tid.size(), got.out(), nullptr);
    EXPECT_EQ(nw, ng);
    for (size_t r = 0; r < want.rays.size(); ++r) {
      EXPECT_EQ(want.prim[r], got.prim[r]) << "seed " << seed << " ray " << r;
      EXPECT_TRUE(same_bits(want.rays[r].t, got.rays[r].t)) << "seed " << seed << " ray " << r;
      EXPECT_TRUE(same_bits(want.u[r], got.u[r]) && same_bits(want.v[r], got.v[r])) << "seed " << seed << " ray " << r;
      hits += want.prim[r] != kInvalidId;
    }
    // Any hit: the same rays blocked and retired, each counted up to its first hit.
    LeafCase wa = make_case(seed), ga = make_case(seed);
    const uint64_t aw = leaf_occluded(wa.rays.data(), wa.pre.data(), rid.data(), rid.size(), wa.tris.data(),
                                      tid.data(), tid.size(), wa.occ.data());
    const uint64_t ag = leaf_few_rays<true>(ga.rays.data(), ga.pre.data(), rid.data(), rid.size(), ga.tris.data(),
                                            tid.data(), tid.size(), ga.out(), ga.occ.data());
    EXPECT_EQ(aw, ag) << "seed " << seed;
    EXPECT_EQ(wa.occ, ga.occ) << "seed " << seed;
    for (size_t r = 0; r < wa.rays.size(); ++r) EXPECT_TRUE(same_bits(wa.rays[r].t, ga.rays[r].t));
    for (uint8_t o : wa.occ) blocked += o;
  }
  EXPECT_GT(hits, 60);     // most of the 7 x 20 rays hit, the live ones included
  EXPECT_GT(blocked, 60);
}
#else
TEST(DacrtLeafKernels, FewRaysKernelEqualsScalarBitForBit) {
  GTEST_SKIP() << "leaf_few_rays is an AVX-512 kernel; this build has no AVX-512";
}
#endif

}  // namespace
}  // namespace rayscout::dacrt
