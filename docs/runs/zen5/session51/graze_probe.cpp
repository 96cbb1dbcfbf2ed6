// Session 51's grazing-ray probe (not part of the build). From the repository root, after a Release build:
//   g++ -std=c++20 -O2 -march=native -ffp-contract=off -Iinclude -Itests/support graze_probe.cpp build/tests/support/librayscout_test_support.a \
//     build/src/{accelerators,shafts,dacrt,embree,bvh,scene,core}/librayscout_*.a -lembree3 -lassimp -lfmt -ltbb -lgtest -lpthread -o graze
// (the libraries in that order). Usage: graze [rays per mesh]; DUMP=i,j,... prints those rays of the random soup with exact plane distances.
// Grazing-ray fuzz: rays at 1e-7..1e-2 rad to a random triangle's plane, aimed at a point inside
// it, on generated meshes; every accelerator against brute (hit/miss, triangle unless t ties).
#include <cmath>
#include <cstdio>
#include <random>
#include <cstdlib>
#include <string>
#include <algorithm>
#include "generated_scenes.h"
#include "rayscout/accelerators.h"
using namespace rayscout;
int main(int argc, char** argv) {
  const size_t per_mesh = argc > 1 ? size_t(std::atol(argv[1])) : 100000;
  struct M { const char* name; std::vector<Triangle> tris; };
  std::vector<M> meshes = {{"random_soup", testing::random_soup(3000, 7)}, {"slivers", testing::slivers(3000, 8)},
                           {"coplanar_duplicates", testing::coplanar_duplicates(1500, 9)}, {"grid", testing::grid(40)},
                           {"sphere", testing::sphere({0, 0, 0}, 1.0f, 5)}};
  const char* names[] = {"bvh2", "bvh", "dacrt", "dacrt-rs", "shafts", "shafts-wide", "embree"};
  for (auto& m : meshes) {
    Scene s = testing::scene_from_triangles(m.tris);
    std::mt19937 rng(123);
    std::uniform_real_distribution<float> U(0.0f, 1.0f);
    RayBatch rays;
    for (size_t i = 0; i < per_mesh; ++i) {
      const Triangle& t = s.triangles[rng() % s.triangles.size()];
      float a = U(rng), b = U(rng);
      if (a + b > 1) { a = 1 - a; b = 1 - b; }
      const Vec3 p = t.v0 + (t.v1 - t.v0) * a + (t.v2 - t.v0) * b;
      const Vec3 n = normalize(t.normal());
      if (!(length(t.normal()) > 0)) continue;
      Vec3 e = normalize(t.v1 - t.v0);
      // A direction in the plane, rotated out of it by a tiny angle.
      const float phi = 6.2831853f * U(rng);
      const Vec3 f = normalize(cross(n, e));
      const Vec3 inplane = e * std::cos(phi) + f * std::sin(phi);
      const float ang = std::pow(10.0f, -7.0f + 5.0f * U(rng)) * (U(rng) < 0.5f ? -1.0f : 1.0f);
      const Vec3 d = normalize(inplane * std::cos(ang) + n * std::sin(ang));
      const float dist = 0.01f + U(rng);
      Ray r{p - d * dist, 0.0f, d, kInfinity};
      rays.push_back(r);
    }
    auto brute = make_accelerator("brute", s);
    HitBatch ref; brute->intersect(rays, ref);
    std::vector<uint8_t> ref_occ; brute->occluded(rays, ref_occ);
    printf("%s: %zu triangles, %zu rays\n", m.name, s.triangles.size(), rays.size());
    if (const char* dump = std::getenv("DUMP"); dump && std::string(m.name) == "random_soup") {
      for (const char* tok = dump; *tok;) {
        char* end; const long k = std::strtol(tok, &end, 10); tok = *end ? end + 1 : end;
        const Ray& r = rays[size_t(k)];
        printf("ray %ld: o (%.9g %.9g %.9g) d (%.9g %.9g %.9g)\n", k, r.org.x, r.org.y, r.org.z, r.dir.x, r.dir.y, r.dir.z);
        auto exact = [&](uint32_t id) {
          const Triangle& t = s.triangles[id];
          const double o[3] = {r.org.x, r.org.y, r.org.z}, d[3] = {r.dir.x, r.dir.y, r.dir.z};
          const double a[3] = {t.v0.x, t.v0.y, t.v0.z}, b[3] = {t.v1.x, t.v1.y, t.v1.z}, c[3] = {t.v2.x, t.v2.y, t.v2.z};
          double e1[3], e2[3], n[3];
          for (int i = 0; i < 3; ++i) e1[i] = b[i] - a[i], e2[i] = c[i] - a[i];
          n[0] = e1[1]*e2[2]-e1[2]*e2[1]; n[1] = e1[2]*e2[0]-e1[0]*e2[2]; n[2] = e1[0]*e2[1]-e1[1]*e2[0];
          double num = 0, den = 0, nn = 0, dd = 0;
          for (int i = 0; i < 3; ++i) num += n[i]*(a[i]-o[i]), den += n[i]*d[i], nn += n[i]*n[i], dd += d[i]*d[i];
          // box entry/exit
          double tn = -1e300, tf = 1e300;
          for (int i = 0; i < 3; ++i) {
            double lo = std::min({a[i], b[i], c[i]}), hi = std::max({a[i], b[i], c[i]});
            double t0 = (lo - o[i]) / d[i], t1 = (hi - o[i]) / d[i];
            if (t0 > t1) std::swap(t0, t1);
            tn = std::max(tn, t0); tf = std::min(tf, t1);
          }
          const double sinang = den / std::sqrt(nn * dd);
          const RayPrecomp rp(r.dir); float ft, fu, fv;
          const bool fh = intersect_triangle(r.org, rp, t, 0.0f, kInfinity, ft, fu, fv);
          printf("  tri %u: exact plane t %.9g, sin(angle) %.3g, box [%.9g, %.9g]; float test %s t %.9g\n", id, num / den, sinang, tn, tf, fh ? "hit" : "miss", ft);
        };
        HitBatch h1; RayBatch one; one.push_back(r); brute->intersect(one, h1);
        exact(h1.prim[0]);
        auto bv = make_accelerator("bvh2", s); HitBatch h2; bv->intersect(one, h2); exact(h2.prim[0]);
      }
    }
    for (const char* nm : names) {
      std::unique_ptr<Accelerator> acc;
      try { acc = make_accelerator(nm, s); } catch (...) { continue; }
      HitBatch h; acc->intersect(rays, h);
      std::vector<uint8_t> occ; acc->occluded(rays, occ);
      size_t hitmiss = 0, other = 0, occd = 0;
      for (size_t i = 0; i < rays.size(); ++i) {
        const bool a = ref.prim[i] != kInvalidId, b = h.prim[i] != kInvalidId;
        if (a != b) { ++hitmiss; if (hitmiss <= 2) printf("   %s ray %zu: brute %u t=%.9g, %s %u t=%.9g\n", nm, i, ref.prim[i], ref.t[i], nm, h.prim[i], h.t[i]); }
        else if (a && ref.prim[i] != h.prim[i] && std::fabs(ref.t[i] - h.t[i]) > 1e-6f * std::max(1.0f, std::fabs(ref.t[i]))) {
          ++other; if (other <= 3) printf("   %s ray %zu: brute %u t=%.9g, %s %u t=%.9g\n", nm, i, ref.prim[i], ref.t[i], nm, h.prim[i], h.t[i]); }
        if ((occ[i] != 0) != (ref_occ[i] != 0)) ++occd;
      }
      printf("  %-12s hit/miss %zu, other triangle %zu, occluded %zu\n", nm, hitmiss, other, occd);
    }
  }
}
