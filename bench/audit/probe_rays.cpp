// probe_rays: ray sets aimed at a scene's own triangles, for the Embree agreement audit.
//
// The families continue adversarial_rays.py's A..H (random rays from the scene box) with rays that
// meet the geometry where accelerators are most likely to disagree. I_vertices: from a point of
// the box grown by 20 % (a quarter from a sphere 2-60 diagonals around it) exactly at a vertex of
// a random triangle. J_edges: likewise at a point of an edge (its midpoint for a third).
// K_in_plane: from the plane of a triangle, 1-3 triangle sizes from its centroid, towards a point
// of the triangle, tilted out of the plane by 0, 1e-7, 1e-5 or 1e-3 rad. L_surface: from a point
// of a triangle in a random direction (a ray leaving its own surface). M_bundles: 64 rays from one
// point with directions jittered by 1e-6..1e-3 rad around a vertex, alternating with 64 parallel
// rays on an 8x8 grid (spacing 1e-4..1e-2 diagonals) around a line through an edge point.
// Aims are computed in double from the float origin (K: from the exact in-plane one), then rounded
// to float as the file stores them. Deterministic: the same scene, N and seed give the same bytes.
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <numbers>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include "rayscout/core/dvec3.h"
#include "rayscout/core/input_error.h"
#include "rayscout/core/random.h"
#include "rayscout/core/ray_file.h"
#include "rayscout/scene/load_scene.h"

namespace rayscout {
namespace {

struct Rng {
  SplitMix64 sm;
  double uniform() { return double(sm.next() >> 11) * 0x1p-53; }  // [0, 1), all 53 bits
  double uniform(double a, double b) { return a + (b - a) * uniform(); }
  double log_uniform(double a, double b) { return std::exp(uniform(std::log(a), std::log(b))); }
  size_t index(size_t n) { return size_t(sm.next() % n); }  // the bias of % is below 2^-40 here
  DVec3 direction() {
    const double z = uniform(-1, 1), phi = 2 * std::numbers::pi * uniform(), r = std::sqrt(1 - z * z);
    return {r * std::cos(phi), r * std::sin(phi), z};
  }
};

// Everything a family draws from: the scene's triangles as double corners, its box and the RNG.
// Two draws never meet in one call's arguments or one operator's operands (a braced list is fine):
// their order would be unspecified, and the bytes must not depend on the compiler.
struct Prober {
  const Scene& scene;
  DVec3 lo, ext, centre;
  double diag;
  Rng rng;

  Prober(const Scene& s, uint64_t seed) : scene(s), rng{SplitMix64{mix64(seed)}} {
    const Bounds3 b = s.bounds();
    lo = DVec3(b.lo), ext = DVec3(b.hi) - lo, centre = lo + ext * 0.5, diag = length(ext);
  }
  DVec3 corner(size_t tri, int k) const {
    const Triangle& t = scene.triangles[tri];
    return DVec3(k == 0 ? t.v0 : k == 1 ? t.v1 : t.v2);
  }
  size_t triangle() { return rng.index(scene.triangles.size()); }
  DVec3 vertex() {
    const size_t t = triangle();
    return corner(t, int(rng.index(3)));
  }
  DVec3 edge_point(bool midpoints) {
    const size_t t = triangle();
    const int k = int(rng.index(3));
    const DVec3 a = corner(t, k), b = corner(t, (k + 1) % 3);
    return a + (b - a) * (midpoints && rng.index(3) == 0 ? 0.5 : rng.uniform());
  }
  DVec3 surface_point(size_t t) {
    const double su = std::sqrt(rng.uniform()), b1 = 1 - su, b2 = rng.uniform() * su;  // as sample_triangle
    return corner(t, 0) + (corner(t, 1) - corner(t, 0)) * b1 + (corner(t, 2) - corner(t, 0)) * b2;
  }
  // The float origin of an aimed ray: the box grown by 20 %, or (a quarter) far outside it.
  Vec3 origin() {
    if (rng.index(4) == 0) {
      const DVec3 dir = rng.direction();
      return to_float(centre + dir * (diag * rng.uniform(2, 60)));
    }
    const DVec3 u{rng.uniform(), rng.uniform(), rng.uniform()};
    return to_float(lo - ext * 0.2 + DVec3{u.x * ext.x, u.y * ext.y, u.z * ext.z} * 1.4);
  }
  // A ray from float `org` whose point at t = 1 is `target` (up to the rounding of the direction).
  static Ray aimed(const Vec3& org, const DVec3& target) { return {org, 0.0f, to_float(target - DVec3(org)), kInfinity}; }

  Ray vertex_ray() { const Vec3 o = origin(); return aimed(o, vertex()); }
  Ray edge_ray() { const Vec3 o = origin(); return aimed(o, edge_point(true)); }

  Ray in_plane_ray() {
    const size_t t = triangle();
    const DVec3 a = corner(t, 0), e1 = corner(t, 1) - a, e2 = corner(t, 2) - a;
    const DVec3 n = normalize(cross(e1, e2)), u = normalize(e1), w = cross(n, u);
    const double size = std::max({length(e1), length(e2), length(e2 - e1)});
    // The centroid is less than the longest edge from every point of the triangle: outside.
    const double phi = 2 * std::numbers::pi * rng.uniform(), r = size * rng.uniform(1, 3);
    const DVec3 o = (a + (e1 + e2) * (1.0 / 3)) + (u * std::cos(phi) + w * std::sin(phi)) * r;
    // The direction lies in the exact plane; only the origin's rounding to float leaves it.
    const DVec3 d = surface_point(t) - o;
    static constexpr double kTilts[] = {0.0, 1e-7, 1e-5, 1e-3};
    const double tilt = kTilts[rng.index(4)], sign = rng.index(2) ? 1 : -1;
    return {to_float(o), 0.0f, to_float(d * std::cos(tilt) + n * (sign * length(d) * std::sin(tilt))), kInfinity};
  }

  Ray surface_ray() { return {to_float(surface_point(triangle())), 0.0f, to_float(rng.direction()), kInfinity}; }

  // Bundle `b` of 64 rays: even ones share an origin, odd ones a direction.
  void bundle(size_t b, size_t count, RayBatch& out) {
    if (b % 2 == 0) {
      const Vec3 o = origin();
      const DVec3 d = DVec3(aimed(o, vertex()).dir);
      const double spread = rng.log_uniform(1e-6, 1e-3);
      for (size_t i = 0; i < count; ++i)
        out.push_back({o, 0.0f, to_float(i == 0 ? d : (normalize(d) + rng.direction() * spread) * length(d)), kInfinity});
      return;
    }
    const Vec3 o = origin();
    const Ray axis = aimed(o, edge_point(false));
    const DVec3 n = normalize(DVec3(axis.dir)), s = normalize(cross(n, std::abs(n.x) < 0.5 ? DVec3{1, 0, 0} : DVec3{0, 1, 0}));
    const DVec3 t = cross(n, s);
    const double h = diag * rng.log_uniform(1e-4, 1e-2);
    // Grid offsets -4..3 steps: the line itself is one of the 64.
    for (size_t i = 0; i < count; ++i)
      out.push_back({to_float(DVec3(axis.org) + s * (h * (double(i % 8) - 4)) + t * (h * (double(i / 8) - 4))), 0.0f,
                     axis.dir, kInfinity});
  }
};

size_t parse_count(const std::string& text) {
  constexpr uint64_t kMax = 100'000'000;  // 3.2 GB per file
  uint64_t n = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
  if (ec != std::errc() || end != text.data() + text.size() || n == 0 || n > kMax)
    throw InputError(fmt::format("N '{}': expected a whole number from 1 to {}", printable(text), kMax));
  return size_t(n);
}

int run(const std::string& scene_arg, const std::filesystem::path& out_dir, const std::string& count, uint64_t seed) {
  const size_t n = parse_count(count);
  if (!std::filesystem::is_directory(out_dir))
    throw InputError(fmt::format("OUT_DIR '{}': no such directory", printable(out_dir.string())));
  const Scene scene = resolve_scene(scene_arg);
  if (scene.triangles.empty()) throw InputError(fmt::format("{}: no triangles (empty scene)", printable(scene_arg)));

  uint64_t family = 0;
  const auto write = [&](const char* name, const std::function<void(Prober&, RayBatch&)>& add) {
    // Each family its own stream, so that changing one family leaves the others' bytes alone.
    Prober p(scene, seed * 16 + family++);
    RayBatch rays;
    rays.reserve(n);
    while (rays.size() < n) add(p, rays);
    const std::filesystem::path file = out_dir / name;
    write_rays(file, rays);
    fmt::print("wrote {} rays to {}\n", rays.size(), file.string());
  };
  write("I_vertices.rays", [](Prober& p, RayBatch& r) { r.push_back(p.vertex_ray()); });
  write("J_edges.rays", [](Prober& p, RayBatch& r) { r.push_back(p.edge_ray()); });
  write("K_in_plane.rays", [](Prober& p, RayBatch& r) { r.push_back(p.in_plane_ray()); });
  write("L_surface.rays", [](Prober& p, RayBatch& r) { r.push_back(p.surface_ray()); });
  write("M_bundles.rays", [n](Prober& p, RayBatch& r) { p.bundle(r.size() / 64, std::min<size_t>(64, n - r.size()), r); });
  return 0;
}

}  // namespace
}  // namespace rayscout

int main(int argc, char** argv) {
  CLI::App app{"probe_rays: ray sets aimed at a scene's own vertices, edges, planes and surfaces (RAYS v1 files "
               "I_vertices .. M_bundles in OUT_DIR, N rays each), for bench/audit's comparison with Embree"};
  std::string scene, count = "35036";
  std::filesystem::path out_dir;
  uint64_t seed = 7;
  app.add_option("SCENE", scene, "Scene or mesh file, or cornell for the built-in box")->required();
  app.add_option("OUT_DIR", out_dir, "Existing folder for the ray files")->required();
  app.add_option("N", count, "Rays per file")->capture_default_str();
  app.add_option("--seed", seed, "Random seed")->capture_default_str();
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return fmt::format("probe_rays: error: {}\nRun 'probe_rays --help' for the options.\n", rayscout::printable(e.what()));
  });
  try {
    app.parse(argc, argv);
    return rayscout::run(scene, out_dir, count, seed);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;  // usage errors exit 2, like bad input (rayscout's convention)
  } catch (const std::exception& e) {
    fmt::print(stderr, "probe_rays: error: {}\n", rayscout::printable(e.what()));
    return 2;
  }
}
