// DACRT's SIMD ray-box kernels against the scalar test: the sample-ray votes of Algorithm 2
// (every rule; the literal rule is the paper's) and ray partitioning.
#include <gtest/gtest.h>

#include <bit>
#include <cfloat>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "box_kernels.h"  // private: src/dacrt

namespace rayscout::dacrt {
namespace {

RayRecord record(Vec3 o, Vec3 d, float t = kInfinity) {
  return {o.x, o.y, o.z, 0.0f, 1.0f / d.x, 1.0f / d.y, 1.0f / d.z, t};
}

// The ray moved into a plane of box b, its direction along that axis +0 or -0 (inverse
// +-inf, so 0 * inf = NaN on the plane): where a kernel choosing planes by comparing the two
// distances differs from core's choice by sign.
RayRecord in_plane_of(const Bounds3& b, int q, RayRecord r) {
  const int axis = (q / 4) % 3;
  const float plane = (q / 12) % 2 ? b.hi[axis] : b.lo[axis];
  const float inv = (q / 24) % 2 ? -kInfinity : kInfinity;
  (axis == 0 ? r.ox : axis == 1 ? r.oy : r.oz) = plane;
  (axis == 0 ? r.ix : axis == 1 ? r.iy : r.iz) = inv;
  return r;
}

TEST(DacrtVotes, LiteralRuleIsAlgorithm2AsPrinted) {
  const float inf = kInfinity;
  // Lines 10-14: n_L when d_L < d_R, d = inf on a miss; everything else votes R.
  EXPECT_EQ(vote(DacrtVotes::Literal, true, true, 1.0f, 2.0f, 3.0f, 4.0f, false), 0);
  EXPECT_EQ(vote(DacrtVotes::Literal, true, true, 3.0f, 4.0f, 1.0f, 2.0f, true), 1);
  EXPECT_EQ(vote(DacrtVotes::Literal, true, false, 5.0f, 6.0f, inf, inf, false), 0);   // only L hit
  EXPECT_EQ(vote(DacrtVotes::Literal, false, true, inf, inf, 5.0f, 6.0f, true), 1);    // only R hit
  EXPECT_EQ(vote(DacrtVotes::Literal, false, false, inf, inf, inf, inf, true), 1);     // neither: R
  EXPECT_EQ(vote(DacrtVotes::Literal, true, true, 0.0f, 1.0f, 0.0f, 2.0f, true), 1);   // inside both: R
  // The other rules count only rays that hit both boxes.
  for (DacrtVotes r : {DacrtVotes::Entry, DacrtVotes::Sign, DacrtVotes::Interval}) {
    EXPECT_EQ(vote(r, true, false, 1.0f, 2.0f, inf, inf, true), -1);
    EXPECT_EQ(vote(r, false, false, inf, inf, inf, inf, true), -1);
  }
  EXPECT_EQ(vote(DacrtVotes::Entry, true, true, 0.0f, 1.0f, 0.0f, 2.0f, true), 0);     // tie: direction
  EXPECT_EQ(vote(DacrtVotes::Interval, true, true, 0.0f, 3.0f, 1.0f, 2.0f, true), -1); // overlapping
  EXPECT_EQ(vote(DacrtVotes::Interval, true, true, 2.5f, 3.0f, 1.0f, 2.0f, true), 1);
}

TEST(DacrtVotes, DepthWeightedOrderWeighsEachSideByTheOtherSubtreesDepth) {
  // Algorithm 1, line 18: the majority, a tie to the left, whatever the children's sizes.
  EXPECT_EQ(first_child_by_votes(3, 2, 8, 1000, false), 0);
  EXPECT_EQ(first_child_by_votes(2, 2, 1000, 8, false), 0);
  EXPECT_EQ(first_child_by_votes(2, 3, 1000, 8, false), 1);
  // Children of one size: the majority again.
  EXPECT_EQ(first_child_by_votes(3, 2, 100, 100, true), 0);
  EXPECT_EQ(first_child_by_votes(2, 3, 100, 100, true), 1);
  EXPECT_EQ(first_child_by_votes(2, 2, 100, 100, true), 0);
  // 2 votes left, 1 right, but the left subtree is log2(1001) = 9.97 deep and the right
  // log2(9) = 3.17: the two right voters would cross 9.97 in vain, the left ones 3.17 each.
  EXPECT_EQ(first_child_by_votes(2, 1, 1000, 8, true), 1);  // 2 * 3.17 < 1 * 9.97
  EXPECT_EQ(first_child_by_votes(4, 1, 1000, 8, true), 0);  // 4 * 3.17 > 1 * 9.97
  EXPECT_EQ(first_child_by_votes(1, 0, 1000000, 8, true), 0);  // unanimous stays unanimous
  EXPECT_EQ(first_child_by_votes(0, 1, 8, 1000000, true), 1);
}

TEST(DacrtVotes, KernelCountsWhatTheScalarRuleGives) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-4.0f, 4.0f), s(0.1f, 3.0f);
  for (DacrtVotes rule : {DacrtVotes::Entry, DacrtVotes::Sign, DacrtVotes::Interval, DacrtVotes::Literal}) {
    BoxSoa lb, rb;
    const int n = 45;  // not a multiple of 16: padding lanes too
    lb.resize(n);
    rb.resize(n);
    std::vector<Bounds3> l(n), r(n);
    for (int j = 0; j < n; ++j) {
      const Vec3 cl{u(rng), u(rng), u(rng)}, cr{u(rng), u(rng), u(rng)};
      const Vec3 hl{s(rng), s(rng), s(rng)}, hr{s(rng), s(rng), s(rng)};
      l[j] = {cl - hl, cl + hl};
      r[j] = j % 7 == 0 ? l[j] : Bounds3{cr - hr, cr + hr};  // identical boxes: equal entries
      lb.set(j, l[j]);
      rb.set(j, r[j]);
    }
    alignas(64) uint32_t c[4][256] = {};
    std::vector<uint32_t> want[4];
    for (auto& w : want) w.assign(size_t(n), 0);
    uint64_t votes = 0;
    for (int q = 0; q < 300; ++q) {
      RayRecord ray = record({u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}, q % 3 ? kInfinity : s(rng));
      if (q % 4 == 0) ray = in_plane_of(l[size_t(q) % size_t(n)], q, ray);
      const bool up = q % 2 == 0;
      sample_pairs(ray, lb, rb, up, rule, c[0], c[1], c[2], c[3]);
      for (int j = 0; j < n; ++j) {
        float dl, fl, dr, fr;
        const bool hl = ray_hits_box(ray, l[size_t(j)], dl, fl), hr = ray_hits_box(ray, r[size_t(j)], dr, fr);
        want[0][size_t(j)] += hl;
        want[1][size_t(j)] += hr;
        const int v = vote(rule, hl, hr, dl, fl, dr, fr, up);
        if (v >= 0) ++want[2 + v][size_t(j)], ++votes;
      }
    }
    for (int k = 0; k < 4; ++k)
      for (int j = 0; j < n; ++j) EXPECT_EQ(c[k][j], want[k][size_t(j)]) << "rule " << int(rule) << " counter " << k << " pair " << j;
    if (rule == DacrtVotes::Literal) EXPECT_EQ(votes, 300u * n);  // every ray votes for every pair
    else EXPECT_GT(votes, 0u);
  }
}

// sample_children (16 sample rays per box test with AVX-512) counts the hits and votes of the
// scalar ray_hits_box and vote() for a chosen split: every rule, tails of 1-15 rays, rays in
// box planes, retired rays, boxes that share a face or are identical.
TEST(DacrtVotes, ChildSamplesCountWhatTheScalarRuleGives) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> u(-4.0f, 4.0f), s(0.1f, 3.0f);
  std::vector<RayRecord> rays(700);
  const Bounds3 pairs[4][2] = {
      {{{-1.0f, -1.0f, -1.0f}, {0.0f, 1.0f, 1.0f}}, {{0.0f, -1.0f, -1.0f}, {1.0f, 1.0f, 1.0f}}},  // one face
      {{{-2.0f, -0.5f, 0.0f}, {1.0f, 0.5f, 2.0f}}, {{-2.0f, -0.5f, 0.0f}, {1.0f, 0.5f, 2.0f}}},   // identical
      {{{-3.0f, 0.5f, -1.0f}, {-1.0f, 2.5f, 3.0f}}, {{0.5f, -2.0f, -3.0f}, {2.0f, 0.0f, -1.0f}}},  // apart
      {{{-3.0f, -1.0f, -1.0f}, {-0.5f, 1.0f, 1.0f}}, {{0.5f, -1.0f, -1.0f}, {3.0f, 1.0f, 1.0f}}}}; // a gap
  for (size_t i = 0; i < rays.size(); ++i) {
    // Aimed at a point of one box of a pair (the other one is often crossed too), or random.
    const Bounds3& aim = pairs[i % 4][(i / 4) % 2];
    const Vec3 o{u(rng), u(rng), u(rng)};
    const Vec3 p = aim.lo + (aim.hi - aim.lo) * Vec3(s(rng), s(rng), s(rng)) * (1.0f / 3.0f);
    const Vec3 d = i % 5 ? p - o : Vec3(u(rng), u(rng), u(rng));
    rays[i] = record(o, d, i % 3 ? kInfinity : s(rng));
    if (i % 4 == 1) rays[i] = in_plane_of(pairs[i % 3][(i / 4) % 2], int(i), rays[i]);
    if (i % 11 == 0) rays[i].ox = 0.0f;  // on the face the first pair shares: exit = entry
    if (i % 37 == 0) (i % 3 == 0 ? rays[i].ix : i % 3 == 1 ? rays[i].iy : rays[i].iz) = i % 2 ? 0.0f : -0.0f;
    if (i % 29 == 0) retire(rays[i]);
    if (i % 31 == 0) rays[i].tmin = kInfinity;  // segments at infinity (filter_tmin, filter_tmax)
    if (i % 41 == 0) rays[i].t = -kInfinity;
  }
  for (DacrtVotes rule : {DacrtVotes::Entry, DacrtVotes::Sign, DacrtVotes::Interval, DacrtVotes::Literal}) {
    uint64_t rule_votes[2] = {0, 0};
    for (const auto& box : pairs)
      for (int axis = 0; axis < 3; ++axis)
        for (size_t ns : {1u, 15u, 16u, 17u, 100u, 233u}) {
          auto id = [&](size_t q) { return (q * 3 + size_t(axis)) % rays.size(); };
          uint32_t hits[2], votes[2], want_hits[2] = {0, 0}, want_votes[2] = {0, 0};
          sample_children(rays.data(), ns, id, box, axis, rule, hits, votes);
          for (size_t q = 0; q < ns; ++q) {
            const RayRecord& r = rays[id(q)];
            float d[2], f[2];
            bool h[2];
            for (int c = 0; c < 2; ++c) want_hits[c] += h[c] = ray_hits_box(r, box[c], d[c], f[c]);
            const int v = vote(rule, h[0], h[1], d[0], f[0], d[1], f[1], r.goes_up(axis));
            if (v >= 0) ++want_votes[v];
          }
          const std::string at = "rule " + std::to_string(int(rule)) + " axis " + std::to_string(axis) + " ns " +
                                 std::to_string(ns);
          EXPECT_EQ(hits[0], want_hits[0]) << at;
          EXPECT_EQ(hits[1], want_hits[1]) << at;
          EXPECT_EQ(votes[0], want_votes[0]) << at;
          EXPECT_EQ(votes[1], want_votes[1]) << at;
          rule_votes[0] += votes[0];
          rule_votes[1] += votes[1];
          if (rule == DacrtVotes::Literal) {
            EXPECT_EQ(votes[0] + votes[1], ns) << at;  // every ray votes
          }
        }
    // Both sides get votes (the interval rule only from rays that cross one box wholly first).
    const uint64_t least = rule == DacrtVotes::Interval ? 30 : 200;
    EXPECT_GT(rule_votes[0], least) << "rule " << int(rule);
    EXPECT_GT(rule_votes[1], least) << "rule " << int(rule);
  }
}

// The filter's limits at infinity are bvh's CullInterval ones: t = -inf keeps every box
// (tmax +inf), tmin = +inf too (tmin -inf); a retired ray (NaN tmin) fails every box test.
// With AVX-512 the 16-lane forms give the scalar ones bit for bit.
TEST(DacrtBoxKernels, FilterLimitsAtInfinityAreCullIntervals) {
  const float inf = kInfinity, nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(filter_tmax(-inf), inf);
  EXPECT_EQ(filter_tmax(inf), inf);
  EXPECT_TRUE(std::isnan(filter_tmax(nan)));
  EXPECT_GT(filter_tmax(-1e30f), -1e30f);
  EXPECT_EQ(filter_tmin(inf), -inf);
  EXPECT_EQ(filter_tmin(-inf), -inf);
  EXPECT_EQ(filter_tmin(2.0f), 2.0f);
  EXPECT_TRUE(std::isnan(filter_tmin(nan)));
  const Bounds3 box{{-1e30f, -1e30f, -1e30f}, {1e30f, 1e30f, 1e30f}};
  RayRecord r = record({0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f});
  float tnear;
  EXPECT_TRUE(ray_hits_box(r, box, tnear));
  r.tmin = inf;  // the segment [+inf, +inf]
  EXPECT_TRUE(ray_hits_box(r, box, tnear));
  r.tmin = -inf;
  r.t = -inf;    // [-inf, -inf], or a hit at -inf
  EXPECT_TRUE(ray_hits_box(r, box, tnear));
  retire(r);
  EXPECT_TRUE(retired(r));
  EXPECT_FALSE(ray_hits_box(r, box, tnear));
#if defined(__AVX512F__)
  const float v[16] = {inf, -inf, nan, 0.0f, -0.0f, 1.0f, -1.0f, 1e-45f, -1e-45f, 3e38f, -3e38f, FLT_MAX, -FLT_MAX,
                       0.5f, -7.25f, 1e-40f};
  alignas(64) float lo[16], hi[16];
  _mm512_store_ps(lo, filter_tmin16(_mm512_loadu_ps(v)));
  _mm512_store_ps(hi, filter_tmax16(_mm512_loadu_ps(v)));
  for (int k = 0; k < 16; ++k) {
    EXPECT_EQ(std::bit_cast<uint32_t>(lo[k]), std::bit_cast<uint32_t>(filter_tmin(v[k]))) << v[k];
    // +-0 may differ in sign only (max_ps's operand order), which no comparison sees.
    EXPECT_TRUE(std::bit_cast<uint32_t>(hi[k]) == std::bit_cast<uint32_t>(filter_tmax(v[k])) ||
                (hi[k] == 0.0f && filter_tmax(v[k]) == 0.0f)) << v[k];
  }
#endif
}

// partition_rays (AVX-512, AVX2 or scalar, whichever this build has) keeps exactly the rays
// the scalar ray_hits_box keeps, in order, with full chunks, a tail, rays in box planes,
// segments at infinity and retired rays.
TEST(DacrtBoxKernels, PartitionKeepsWhatTheScalarTestKeeps) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-4.0f, 4.0f), s(0.1f, 3.0f);
  const Bounds3 box{{-1.0f, -0.5f, -2.0f}, {1.5f, 2.0f, 0.5f}};
  const size_t n = 16 * 20 + 7;
  std::vector<RayRecord> rays(n);
  for (size_t i = 0; i < n; ++i) {
    rays[i] = record({u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}, i % 3 ? kInfinity : s(rng));
    if (i % 3 == 0) rays[i] = in_plane_of(box, int(i), rays[i]);
    if (i % 5 == 1) rays[i].tmin = kInfinity;
    if (i % 7 == 2) rays[i].t = -kInfinity;
    if (i % 11 == 3) retire(rays[i]);
  }
  std::vector<uint32_t> rid(n), scratch(n), want_in, want_out;
  for (uint32_t i = 0; i < n; ++i) {
    rid[i] = i;
    float tnear;
    (ray_hits_box(rays[i], box, tnear) ? want_in : want_out).push_back(i);
  }
  ASSERT_GT(want_in.size(), 20u);
  ASSERT_GT(want_out.size(), 20u);
  const size_t k = partition_rays(rays.data(), rid.data(), n, box, scratch.data());
  ASSERT_EQ(k, want_in.size());
  EXPECT_TRUE(std::equal(want_in.begin(), want_in.end(), rid.begin()));
  EXPECT_TRUE(std::equal(want_out.begin(), want_out.end(), rid.begin() + ptrdiff_t(k)));
}

}  // namespace
}  // namespace rayscout::dacrt
