// The warps of sampling.h against known answers: an orthonormal basis, the moments of the
// cosine-weighted hemisphere and of a uniform point on a triangle.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "rayscout/core/random.h"
#include "rayscout/core/sampling.h"

namespace rayscout {
namespace {

std::vector<Vec3> test_normals() {
  // n.z = -0 takes the negative branch of Duff et al.'s sign.
  std::vector<Vec3> n = {{0, 0, 1}, {0, 0, -1}, {1, 0, -0.0f}, {1, 0, 0}, {0, -1, 0}, normalize(Vec3(1, 2, -3))};
  SplitMix64 rng{7};
  for (int i = 0; i < 100; ++i) {
    const Vec3 v(2 * rng.uniform() - 1, 2 * rng.uniform() - 1, 2 * rng.uniform() - 1);
    if (length(v) > 0.1f) n.push_back(normalize(v));
  }
  return n;
}

TEST(Sampling, OrthonormalBasisIsRightHanded) {
  for (const Vec3& n : test_normals()) {
    Vec3 t, b;
    orthonormal_basis(n, t, b);
    EXPECT_NEAR(length(t), 1.0f, 1e-5f);
    EXPECT_NEAR(length(b), 1.0f, 1e-5f);
    EXPECT_NEAR(dot(t, b), 0.0f, 1e-5f);
    EXPECT_NEAR(dot(t, n), 0.0f, 1e-5f);
    EXPECT_NEAR(dot(b, n), 0.0f, 1e-5f);
    EXPECT_NEAR(length(cross(t, b) - n), 0.0f, 1e-5f) << n.x << " " << n.y << " " << n.z;
  }
}

// pdf cos(theta) / pi: E[cos] = 2/3, E[cos^2] = 1/2, and no preferred azimuth (E[d.t] = E[d.b] = 0).
// Bounds: 5 standard errors of N samples (variances 1/18, 1/12, 1/4).
TEST(Sampling, CosineHemisphereHasTheCosineMoments) {
  const int N = 100000;
  for (const Vec3& n : {Vec3(0, 0, 1), Vec3(0, 0, -1), normalize(Vec3(1, 2, -3))}) {
    Vec3 t, b;
    orthonormal_basis(n, t, b);
    SplitMix64 rng{3};
    double cos1 = 0, cos2 = 0, along_t = 0, along_b = 0;
    for (int i = 0; i < N; ++i) {
      const float u1 = rng.uniform(), u2 = rng.uniform();
      const Vec3 d = sample_cosine_hemisphere(n, u1, u2);
      ASSERT_NEAR(length(d), 1.0f, 1e-5f);
      ASSERT_GE(dot(d, n), -1e-6f);
      cos1 += dot(d, n);
      cos2 += dot(d, n) * dot(d, n);
      along_t += dot(d, t);
      along_b += dot(d, b);
    }
    const double se = 1.0 / std::sqrt(double(N));
    EXPECT_NEAR(cos1 / N, 2.0 / 3.0, 5 * se * std::sqrt(1.0 / 18));
    EXPECT_NEAR(cos2 / N, 0.5, 5 * se * std::sqrt(1.0 / 12));
    EXPECT_NEAR(along_t / N, 0.0, 5 * se * 0.5);
    EXPECT_NEAR(along_b / N, 0.0, 5 * se * 0.5);
  }
}

// A uniform point: every barycentric has mean 1/3 (variance 1/18), and the quarter of the area
// nearest v0 (1 - b1 - b2 >= 1/2) gets a quarter of the points.
TEST(Sampling, TrianglePointsAreUniform) {
  EXPECT_EQ(sample_triangle(0.0f, 0.5f).b1, 1.0f);  // u1 = 0: vertex v1
  EXPECT_EQ(sample_triangle(0.25f, 0.5f).b2, 0.25f);
  const int N = 100000;
  SplitMix64 rng{5};
  double b0 = 0, b1 = 0, b2 = 0, near_v0 = 0;
  for (int i = 0; i < N; ++i) {
    const float u1 = rng.uniform(), u2 = rng.uniform();
    const TriangleSample s = sample_triangle(u1, u2);
    ASSERT_GE(s.b1, 0.0f);
    ASSERT_GE(s.b2, 0.0f);
    ASSERT_LE(s.b1 + s.b2, 1.0f);
    b0 += 1.0 - s.b1 - s.b2;
    b1 += s.b1;
    b2 += s.b2;
    near_v0 += 1.0 - s.b1 - s.b2 >= 0.5;
  }
  const double se = 1.0 / std::sqrt(double(N));
  for (double sum : {b0, b1, b2}) EXPECT_NEAR(sum / N, 1.0 / 3.0, 5 * se * std::sqrt(1.0 / 18));
  EXPECT_NEAR(near_v0 / N, 0.25, 5 * se * std::sqrt(3.0 / 16));
}

}  // namespace
}  // namespace rayscout
