// Core kernels: the watertight triangle test and the robust slab test on their edge cases.
#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include "rayscout/core/dvec3.h"
#include "rayscout/core/triangle.h"

namespace rayscout {
namespace {

const Bounds3 kUnitBox{{0, 0, 0}, {1, 1, 1}};

bool hits_box(const Vec3& org, const Vec3& dir, float& tnear) {
  return intersect_box(org, RayPrecomp(dir).inv_dir, kUnitBox, 0.0f, kInfinity, tnear);
}

TEST(IntersectBox, EntryDistanceOfAnOrdinaryRay) {
  float tnear = -1;
  ASSERT_TRUE(hits_box({-1, 0.5f, 0.5f}, {1, 0, 0}, tnear));
  EXPECT_FLOAT_EQ(tnear, 1.0f);
  EXPECT_FALSE(hits_box({-1, 2.0f, 0.5f}, {1, 0, 0}, tnear));
  EXPECT_FALSE(hits_box({2, 0.5f, 0.5f}, {1, 0, 0}, tnear)) << "box behind the ray";
}

// A ray lying exactly in a face plane, parallel to it, touches the box: with a +0 or -0
// direction component the slab distances are 0 * inf = NaN and must not cull it.
TEST(IntersectBox, RayLyingInAFacePlaneIsKeptForBothSignsOfZero) {
  float tnear;
  for (float zero : {0.0f, -0.0f})
    for (float y : {0.0f, 1.0f}) {
      EXPECT_TRUE(hits_box({-1, y, 0.5f}, {1, zero, 0.25f}, tnear)) << "y=" << y << " dir.y=" << zero;
      EXPECT_TRUE(hits_box({0.5f, y, -1}, {zero, zero, 1}, tnear)) << "y=" << y << " dir.y=" << zero;
    }
  EXPECT_FALSE(hits_box({-1, 1.0001f, 0.5f}, {1, -0.0f, 0}, tnear)) << "just outside the slab";
}

TEST(IntersectBox, FarDistanceIsWidenedNotNarrowed) {
  float tnear;
  // Grazing the far corner: rounding of t must not cull the box.
  EXPECT_TRUE(hits_box({-1, -1, -1}, {1, 1, 1}, tnear));
  EXPECT_FLOAT_EQ(tnear, 1.0f);
  EXPECT_TRUE(intersect_box({-1, 0.5f, 0.5f}, Vec3(1, kInfinity, kInfinity), kUnitBox, 0, 1.0f, tnear))
      << "tmax exactly at the entry";
}

// A ray through the box edge x = 0, y = 1 enters the x slab exactly where it leaves the y slab;
// rounded apart, the entry comes out beyond the exit here, and only the widened far distance
// keeps the box (culling it would lose the triangles on that edge).
TEST(IntersectBox, RayThroughAnEdgeSurvivesRoundingOfItsSlabDistances) {
  const Vec3 org{-1.19918871f, 0.831393242f, 0.5f};
  float tnear;
  EXPECT_TRUE(hits_box(org, Vec3{0, 1, 0.5f} - org, tnear));
  EXPECT_FLOAT_EQ(tnear, 1.0f);
}

TEST(IntersectTriangle, HitDistanceAndBarycentrics) {
  const Triangle tri{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const Vec3 org{0.25f, 0.5f, 2}, dir{0, 0, -1};
  float t, u, v;
  ASSERT_TRUE(intersect_triangle(org, RayPrecomp(dir), tri, 0, kInfinity, t, u, v));
  ASSERT_EQ(t, 2.0f);  // exactly: the segments ending at 2 below rely on it
  EXPECT_FLOAT_EQ(u, 0.25f);
  EXPECT_FLOAT_EQ(v, 0.5f);
  EXPECT_FALSE(intersect_triangle(org, RayPrecomp(dir), tri, 0, 1.5f, t, u, v)) << "beyond tmax";
  // Both ends of [tmin, tmax] are included (the Accelerator contract), a one-point segment too.
  EXPECT_TRUE(intersect_triangle(org, RayPrecomp(dir), tri, 2.0f, kInfinity, t, u, v)) << "at tmin";
  EXPECT_TRUE(intersect_triangle(org, RayPrecomp(dir), tri, 0, 2.0f, t, u, v)) << "at tmax";
  EXPECT_TRUE(intersect_triangle(org, RayPrecomp(dir), tri, 2.0f, 2.0f, t, u, v)) << "tmin = tmax = t";
  EXPECT_FALSE(intersect_triangle(org, RayPrecomp(-dir), tri, 0, kInfinity, t, u, v)) << "behind";
}

// Watertightness: a ray through the common edge of two triangles, or the common vertex of a
// fan, hits at least one of them.
TEST(IntersectTriangle, SharedEdgeAndVertexAreNeverMissed) {
  const Triangle a{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}, b{{0, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  float t, u, v;
  const Vec3 dir{1e-3f, -2e-3f, -1};
  const RayPrecomp rp(dir);
  for (float s : {0.1f, 0.37f, 0.5f, 0.999f}) {
    const Vec3 org = Vec3{s, s, 0} - dir;  // reaches the diagonal (s, s, 0) at t = 1
    const bool hit = intersect_triangle(org, rp, a, 0, kInfinity, t, u, v) ||
                     intersect_triangle(org, rp, b, 0, kInfinity, t, u, v);
    EXPECT_TRUE(hit) << "s=" << s;
  }
  const Vec3 centre{0.3f, 0.7f, 0.2f}, corners[] = {{0, 0, 0}, {1, 0, 0.1f}, {1, 1, 0.3f}, {0, 1, 0.4f}};
  const Vec3 org = centre - dir;
  bool hit = false;
  for (int i = 0; i < 4; ++i)
    hit |= intersect_triangle(org, rp, {centre, corners[i], corners[(i + 1) % 4]}, 0, kInfinity, t, u, v);
  EXPECT_TRUE(hit) << "shared vertex of a fan";
}

// A ray exactly through a shared edge: one edge function is exactly 0 in float, and a zero
// edge function counts as inside, so both triangles report the hit at the same t (the
// closest-hit rule then keeps the smaller id). Rejecting zero would let the ray slip through
// the crack. Every rotation and winding of the corners, so that the zero falls on each of
// the three edge functions, with the other two positive and negative.
TEST(IntersectTriangle, RayExactlyThroughASharedEdgeHitsBothTriangles) {
  const Triangle left{{0, -1, 0}, {0, 1, 0}, {-1, 0, 0}}, right{{0, -1, 0}, {1, 0, 0}, {0, 1, 0}};
  const Vec3 dir{0, 0, 1};
  const RayPrecomp rp(dir);
  for (const Triangle& tri : {left, right})
    for (int rotation = 0; rotation < 3; ++rotation)
      for (const bool flip : {false, true}) {
        const Vec3 c[3] = {tri.v0, tri.v1, tri.v2};
        Triangle x{c[rotation], c[(rotation + 1) % 3], c[(rotation + 2) % 3]};
        if (flip) std::swap(x.v1, x.v2);
        for (const float y : {-0.5f, 0.0f, 0.3f, 0.75f}) {
          float t, u, v;
          ASSERT_TRUE(intersect_triangle({0, y, -1}, rp, x, 0, kInfinity, t, u, v))
              << "y=" << y << " rotation " << rotation << (flip ? " flipped" : "");
          EXPECT_EQ(t, 1.0f);
        }
      }
}

// The edge b-c below lies 1.7e-4 from the ray, but seen from the ray origin its edge function
// c.y b.x - c.x b.y cancels to exactly 0 in float (true value 2^-24). Only the recomputation
// in double tells which side of the shared edge the ray passes: it hits B (at its interior
// point u = v = 1/4) and not A; taken as 0, the edge would count as touched by both.
TEST(IntersectTriangle, EdgeFunctionCancellingToZeroIsDecidedInDouble) {
  const float e11 = std::ldexp(1.0f, -11), e12 = std::ldexp(1.0f, -12), e13 = std::ldexp(1.0f, -13);
  const Vec3 b{1 + e12, 1, 0}, c{1 + e11, 1 + e12, 0};
  const Vec3 mid{1 + 3 * e13, 1 + e13, 0};  // (b + c) / 2, exact
  const Triangle a_side{mid * 2.0f, b, c}, b_side{mid * -1.0f, c, b};  // the ray passes between mid and -mid
  const Vec3 org{0, 0, 1}, dir{0, 0, -1};
  const RayPrecomp rp(dir);
  float t, u, v;
  EXPECT_FALSE(intersect_triangle(org, rp, a_side, 0, kInfinity, t, u, v));
  ASSERT_TRUE(intersect_triangle(org, rp, b_side, 0, kInfinity, t, u, v));
  EXPECT_EQ(t, 1.0f);
  EXPECT_EQ(u, 0.25f);
  EXPECT_EQ(v, 0.25f);
}

// Two overlapping triangles of Sponza's floor trim (ids 49800 and 119889), 1e-4 apart in z, and
// the audit's ray (family H, ray 22268; direction scaled by 2^96) that meets both. 49800 is a
// sliver, 273 x 0.45 units, hit 188 units from its v0. Woop's interpolated t put that hit 59 ulps
// (of 142.85) short of its plane, in front of 119889, which is nearer by 4 ulps; the plane
// distance puts each hit within 1 ulp of its plane, in the right order.
TEST(IntersectTriangle, SliverHitLiesOnItsPlane) {
  const Triangle sliver{{-142.852005f, 0.112262003f, 57.4029007f}, {130.218994f, -0.337967992f, 57.4029999f},
                        {130.218994f, 0.112262003f, 57.4029999f}};
  const Triangle nearer{{2.03048992f, -0.262037992f, 57.4029999f}, {38.1451988f, 12.1583996f, 57.4029999f},
                        {130.218994f, -0.262037992f, 57.4029999f}};
  const Vec3 org{45.0192108f, -10.0714378f, 67.2716293f};
  const Vec3 dir = Vec3(-6.29013535e-29f, 5.1831397e-29f, -5.15610205e-29f) * 0x1p96f;
  const RayPrecomp rp(dir);
  const float ulp = 142.852005f * 0x1p-24f;
  float t_sliver, t_nearer, u, v;
  ASSERT_TRUE(intersect_triangle(org, rp, sliver, 0, kInfinity, t_sliver, u, v));
  ASSERT_TRUE(intersect_triangle(org, rp, nearer, 0, kInfinity, t_nearer, u, v));
  for (const auto& [tri, t] : {std::pair{sliver, t_sliver}, std::pair{nearer, t_nearer}}) {
    const DVec3 n = cross(DVec3(tri.v1) - DVec3(tri.v0), DVec3(tri.v2) - DVec3(tri.v0));
    const double off = dot(n, DVec3(org) + DVec3(dir) * double(t) - DVec3(tri.v0)) / length(n);
    EXPECT_LE(std::fabs(off), ulp) << "t " << t;
  }
  EXPECT_LT(t_nearer, t_sliver);
}

TEST(IsCloser, TiesGoToTheSmallerTriangleId) {
  EXPECT_TRUE(is_closer(1.0f, 5, 2.0f, 1));
  EXPECT_TRUE(is_closer(1.0f, 3, 1.0f, 4));
  EXPECT_FALSE(is_closer(1.0f, 4, 1.0f, 3));
  EXPECT_FALSE(is_closer(1.0f, 4, 1.0f, 4));
}

}  // namespace
}  // namespace rayscout

namespace rayscout {
namespace {

// |a| where the sum of squares over- or underflows but |a| does not: the normal of a triangle
// with edges of 1e10 (squares ~1e40) or of 1e-12 (squares ~1e-48), and the area from it.
TEST(VectorLength, ExactWhereTheSquaresLeaveFloatRange) {
  EXPECT_FLOAT_EQ(length(Vec3(3e19f, 4e19f, 0.0f)), 5e19f);
  EXPECT_FLOAT_EQ(length(Vec3(0.0f, -3e-25f, 4e-25f)), 5e-25f);
  EXPECT_FLOAT_EQ(length(Vec3(2e-30f, 0.0f, 0.0f)), 2e-30f);
  const Vec3 n = normalize(Vec3(3e20f, 0.0f, 4e20f));
  EXPECT_FLOAT_EQ(n.x, 0.6f);
  EXPECT_FLOAT_EQ(n.z, 0.8f);
  const Triangle big{{0, 0, 0}, {1e10f, 0, 0}, {0, 1e10f, 0}};
  EXPECT_FLOAT_EQ(big.area(), 5e19f);
  EXPECT_EQ(length(Vec3(0.0f)), 0.0f);
  EXPECT_EQ(length(Vec3(kInfinity, 1.0f, 0.0f)), kInfinity);
  EXPECT_TRUE(std::isnan(length(Vec3(std::nanf(""), 1.0f, 0.0f))));
  EXPECT_EQ(length(Vec3(3.0f, 4.0f, 0.0f)), 5.0f);  // the usual range: sqrt of the sum, as before
}

}  // namespace
}  // namespace rayscout
