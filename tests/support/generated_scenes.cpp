// Generated test scenes and ray sets.
#include "generated_scenes.h"

#include <array>
#include <cmath>
#include <cstdlib>
#include <map>
#include <numbers>
#include <random>
#include <string_view>

#include "rayscout/core/accelerator.h"

namespace rayscout::testing {

std::vector<Triangle> random_soup(size_t n, uint32_t seed) {
  Rng rng(seed);
  std::vector<Triangle> tris;
  for (size_t i = 0; i < n; ++i) {
    const Vec3 c = rng.point(0.0f, 1.0f);
    const float s = rng.uniform(0.01f, 0.2f);
    tris.push_back({c + rng.direction() * s, c + rng.direction() * s, c + rng.direction() * s});
  }
  return tris;
}

std::vector<Triangle> slivers(size_t n, uint32_t seed) {
  Rng rng(seed);
  std::vector<Triangle> tris;
  for (size_t i = 0; i < n; ++i) {
    const Vec3 a = rng.point(0.0f, 1.0f), d = rng.direction() * rng.uniform(0.2f, 0.8f);
    const Vec3 w = normalize(cross(d, rng.direction())) * 1e-4f;
    tris.push_back({a, a + d, a + d * 0.5f + w});
  }
  return tris;
}

std::vector<Triangle> coplanar_duplicates(size_t n, uint32_t seed) {
  Rng rng(seed);
  std::vector<Triangle> tris;
  for (size_t i = 0; i < n; ++i) {
    auto p = [&] { return Vec3{rng.uniform(), rng.uniform(), 0.5f}; };
    const Triangle t{p(), p(), p()};
    tris.push_back(t);
    tris.push_back(t);
  }
  return tris;
}

std::vector<Triangle> grid(int n) {
  std::vector<Triangle> tris;
  const float h = 1.0f / float(n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const Vec3 a{i * h, j * h, 0}, b{(i + 1) * h, j * h, 0}, c{(i + 1) * h, (j + 1) * h, 0}, d{i * h, (j + 1) * h, 0};
      tris.push_back({a, b, c});
      tris.push_back({a, c, d});
    }
  return tris;
}

std::vector<Triangle> equal_centroids(size_t n, uint32_t seed) {
  Rng rng(seed);
  const Vec3 c{0.5f, 0.5f, 0.5f};
  std::vector<Triangle> tris;
  for (size_t i = 0; i < n; ++i) {
    const Vec3 a = rng.direction() * rng.uniform(0.05f, 0.4f), b = rng.direction() * rng.uniform(0.05f, 0.4f);
    tris.push_back({c + a, c + b, c - a - b});  // centroid exactly c up to rounding
  }
  return tris;
}

std::vector<Triangle> sphere(const Vec3& c, float r, int subdivisions) {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  std::vector<Vec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : v) p = normalize(p);
  std::vector<std::array<uint32_t, 3>> f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11},
                                            {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                            {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9},
                                            {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back(normalize((v[a] + v[b]) * 0.5f));
      return mid[key] = uint32_t(v.size() - 1);
    };
    std::vector<std::array<uint32_t, 3>> next;
    for (auto [a, b, cc] : f) {
      const uint32_t ab = midpoint(a, b), bc = midpoint(b, cc), ca = midpoint(cc, a);
      next.insert(next.end(), {{a, ab, ca}, {b, bc, ab}, {cc, ca, bc}, {ab, bc, ca}});
    }
    f = std::move(next);
  }
  std::vector<Triangle> tris;
  for (auto [a, b, cc] : f) tris.push_back({c + v[a] * r, c + v[b] * r, c + v[cc] * r});
  return tris;
}

std::vector<TestMesh> nasty_meshes() {
  return {{"random_soup", random_soup(3000, 1)},
          {"slivers", slivers(1000, 2)},
          {"coplanar_duplicates", coplanar_duplicates(500, 3)},
          {"grid", grid(24)},
          {"equal_centroids", equal_centroids(600, 4)},
          {"sphere", sphere({0.5f, 0.5f, 0.5f}, 0.4f, 3)},
          {"single_triangle", {{{0.1f, 0.1f, 0.5f}, {0.9f, 0.2f, 0.5f}, {0.3f, 0.9f, 0.5f}}}}};
}

Reference brute_force(const std::vector<Triangle>& tris, const RayBatch& rays) {
  Reference r;
  const BruteForce brute(tris);
  brute.intersect(rays, r.hits);
  brute.occluded(rays, r.occluded);
  return r;
}

bool small_scale() {
  const char* s = std::getenv("RAYSCOUT_TEST_SCALE");
  return s != nullptr && std::string_view(s) == "small";
}

RayBatch random_rays(size_t n, uint32_t seed) {
  Rng rng(seed);
  RayBatch rays;
  for (size_t i = 0; i < n; ++i) rays.push_back({rng.point(-0.5f, 1.5f), 0.0f, rng.direction(), kInfinity});
  return rays;
}

RayBatch axis_parallel_rays(size_t n, uint32_t seed) {
  Rng rng(seed);
  RayBatch rays;
  for (size_t i = 0; i < n; ++i) {
    const int axis = int(i % 3);
    const float sign = (i / 3) % 2 ? 1.0f : -1.0f;
    Vec3 o = rng.point(0.0f, 1.0f), d{0, 0, 0};
    o[axis] = sign > 0 ? -0.5f : 1.5f;
    d[axis] = sign;
    rays.push_back({o, 0.0f, d, kInfinity});
  }
  return rays;
}

RayBatch rays_at_edges_and_vertices(const std::vector<Triangle>& tris, size_t n, uint32_t seed) {
  Rng rng(seed);
  RayBatch rays;
  if (tris.empty()) return rays;
  for (size_t i = 0; i < n; ++i) {
    const Triangle& t = tris[std::min(tris.size() - 1, size_t(rng.uniform() * float(tris.size())))];
    const Vec3 targets[] = {t.v0, t.v1, t.v2, (t.v0 + t.v1) * 0.5f, (t.v1 + t.v2) * 0.5f, (t.v2 + t.v0) * 0.5f};
    const Vec3 target = targets[i % 6];
    const Vec3 o = (i % 4 == 0) ? Vec3{target.x, target.y, target.z + 2.0f} : rng.point(-0.5f, 1.5f);
    rays.push_back({o, 0.0f, target - o, kInfinity});
  }
  return rays;
}

RayBatch rays_from_surfaces(const std::vector<Triangle>& tris, size_t n, uint32_t seed) {
  Rng rng(seed);
  RayBatch rays;
  if (tris.empty()) return rays;
  for (size_t i = 0; i < n; ++i) {
    const Triangle& t = tris[std::min(tris.size() - 1, size_t(rng.uniform() * float(tris.size())))];
    float a = rng.uniform(), b = rng.uniform();
    if (a + b > 1.0f) { a = 1.0f - a; b = 1.0f - b; }
    const Vec3 p = t.v0 * (1.0f - a - b) + t.v1 * a + t.v2 * b;
    rays.push_back({p, 0.0f, rng.direction(), kInfinity});
  }
  return rays;
}

RayBatch nasty_rays(const std::vector<Triangle>& tris, uint32_t seed) {
  RayBatch all;
  for (const RayBatch& part : {random_rays(1500, seed), axis_parallel_rays(300, seed + 1),
                               rays_at_edges_and_vertices(tris, 600, seed + 2),
                               rays_from_surfaces(tris, 300, seed + 3)})
    for (size_t i = 0; i < part.size(); ++i) all.push_back(part[i]);
  // Some rays with a finite tmax, the way shadow rays come.
  for (size_t i = 0; i < all.size(); i += 7) all.tmax[i] = 0.8f;
  return all;
}

Scene scene_from_triangles(std::vector<Triangle> triangles) {
  Scene s;
  s.triangles = std::move(triangles);
  s.materials.push_back(Material{.name = "default"});
  s.material_ids.assign(s.triangles.size(), 0);
  const Bounds3 b = s.bounds();
  s.camera.look_at = b.center();
  s.camera.eye = b.center() + Vec3{0, 0, 2.5f * max_component(b.diagonal())};
  s.point_lights.push_back({s.camera.eye, Vec3{1.0f}});
  return s;
}

}  // namespace rayscout::testing
