// Generated test scenes and ray sets with the nasty cases every accelerator must survive.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "rayscout/core/ray.h"
#include "rayscout/core/triangle.h"
#include "rayscout/scene/scene.h"

namespace rayscout::testing {

/// Deterministic random numbers, points and directions for generated scenes and rays.
struct Rng {
  std::mt19937 gen;
  explicit Rng(uint32_t seed) : gen(seed) {}
  float uniform(float lo = 0.0f, float hi = 1.0f) { return std::uniform_real_distribution<float>(lo, hi)(gen); }
  /// A point with every coordinate uniform in [lo, hi).
  Vec3 point(float lo, float hi) { return {uniform(lo, hi), uniform(lo, hi), uniform(lo, hi)}; }
  /// A unit direction, uniform on the sphere.
  Vec3 direction() {
    const float z = uniform(-1.0f, 1.0f), phi = uniform(0.0f, 2.0f * std::numbers::pi_v<float>);
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    return {r * std::cos(phi), r * std::sin(phi), z};
  }
};

/// True when RAYSCOUT_TEST_SCALE=small (the sanitizer run, 5-10x slower): tests shrink their sizes.
bool small_scale();

/// A named triangle set for parameterised tests.
struct TestMesh {
  std::string name;
  std::vector<Triangle> triangles;
};

/// n random triangles of random size inside the unit cube.
std::vector<Triangle> random_soup(size_t n, uint32_t seed);
/// Long thin triangles (aspect ratio ~1e4) in random orientations.
std::vector<Triangle> slivers(size_t n, uint32_t seed);
/// Coplanar overlapping triangles on z = 0.5, each duplicated once (exact ties).
std::vector<Triangle> coplanar_duplicates(size_t n, uint32_t seed);
/// A regular grid of n x n quads (2 triangles each) on z = 0 spanning [0,1]^2: shared edges and vertices.
std::vector<Triangle> grid(int n);
/// n triangles in random planes all sharing the same centroid (0.5, 0.5, 0.5).
std::vector<Triangle> equal_centroids(size_t n, uint32_t seed);
/// A closed, watertight sphere (subdivided icosahedron) of radius r at c.
std::vector<Triangle> sphere(const Vec3& c, float r, int subdivisions);
/// What brute force answers for a ray batch: the reference of every accelerator test.
struct Reference {
  HitBatch hits;                  ///< closest hits
  std::vector<uint8_t> occluded;  ///< any hit, 1 = occluded
};
/// Traces rays against tris with BruteForce, closest hit and any hit.
Reference brute_force(const std::vector<Triangle>& tris, const RayBatch& rays);

/// Every mesh above, of modest size.
std::vector<TestMesh> nasty_meshes();

/// Random rays from points in [-0.5, 1.5]^3 with random directions.
RayBatch random_rays(size_t n, uint32_t seed);
/// Rays along +-x, +-y, +-z (zero direction components) through the unit cube.
RayBatch axis_parallel_rays(size_t n, uint32_t seed);
/// Rays aimed exactly at vertices and edge midpoints of the given triangles.
RayBatch rays_at_edges_and_vertices(const std::vector<Triangle>& tris, size_t n, uint32_t seed);
/// Rays starting on the surface of triangles (tmin = 0), pointing anywhere.
RayBatch rays_from_surfaces(const std::vector<Triangle>& tris, size_t n, uint32_t seed);
/// All ray sets above for a mesh, concatenated.
RayBatch nasty_rays(const std::vector<Triangle>& tris, uint32_t seed);

/// A Scene wrapping bare triangles (one diffuse material, default camera framing them).
Scene scene_from_triangles(std::vector<Triangle> triangles);

}  // namespace rayscout::testing
