// ShaftsAccelerator on the borders of its classification: geometry lying in voxel planes, rays
// starting on voxel faces, edges and corners, directions along the axes, on the diagonals
// between cube faces and on cell borders, rays from outside grazing the box, very short
// segments and tmin > 0; closest and any hit against brute force.
#include <gtest/gtest.h>

#include <random>

#include "generated_scenes.h"
#include "rayscout/core/hit_compare.h"
#include "rayscout/shafts/shafts_accelerator.h"

namespace rayscout {
namespace {

using Base = ShaftsAccelerator::Base;

/// Quads in the planes x, y or z = k/4 of the unit cube, each a whole cell face or a part of
/// one, plus corner points that make the scene box exactly [0, 1]^3: with 4^3 voxels every
/// quad lies in voxel faces and its edges on voxel edges.
std::vector<Triangle> lattice(int quads, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<Triangle> tris;
  auto quad = [&](int axis, float plane, float u0, float u1, float v0, float v1) {
    const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
    auto p = [&](float u, float v) {
      Vec3 q;
      q[axis] = plane;
      q[ua] = u;
      q[va] = v;
      return q;
    };
    tris.push_back({p(u0, v0), p(u1, v0), p(u1, v1)});
    tris.push_back({p(u0, v0), p(u1, v1), p(u0, v1)});
  };
  for (int i = 0; i < quads; ++i) {
    const int axis = int(rng() % 3), k = int(rng() % 5), cu = int(rng() % 4), cv = int(rng() % 4);
    const float u0 = 0.25f * float(cu), v0 = 0.25f * float(cv);
    if (rng() % 2) quad(axis, 0.25f * float(k), u0, u0 + 0.25f, v0, v0 + 0.25f);  // a whole cell face
    else quad(axis, 0.25f * float(k), u0 + 0.125f, u0 + 0.25f, v0, v0 + 0.125f);  // a quarter of one
  }
  tris.push_back({Vec3{0.0f}, Vec3{0.0f, 0.01f, 0.0f}, Vec3{0.01f, 0.0f, 0.0f}});
  tris.push_back({Vec3{1.0f}, Vec3{1.0f, 0.99f, 1.0f}, Vec3{0.99f, 1.0f, 1.0f}});
  return tris;
}

/// Directions on the borders of the cube map and its cells for d cells per face edge: the
/// axes, the diagonals between two faces (|d[a]| = |d[b]|), the cube corners, and cell
/// borders u, v = -1 + 2k/d on every face, with every sign.
std::vector<Vec3> border_directions(int d) {
  std::vector<Vec3> dirs;
  for (int axis = 0; axis < 3; ++axis)
    for (float s : {1.0f, -1.0f}) {
      const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
      for (int i = 0; i <= d; ++i)
        for (int j = 0; j <= d; ++j) {
          Vec3 dir;
          dir[axis] = s;
          dir[ua] = -1.0f + 2.0f * float(i) / float(d);
          dir[va] = -1.0f + 2.0f * float(j) / float(d);
          dirs.push_back(dir);
        }
      for (float c : {0.0f, 0.3f, -0.6f}) {  // on the diagonal between this face and the next
        Vec3 dir;
        dir[axis] = s;
        dir[ua] = -s;
        dir[va] = c;
        dirs.push_back(dir);
        dir[ua] = s;
        dirs.push_back(dir);
      }
    }
  return dirs;
}

/// Origins on voxel corners, edge and face centres (planes k/4, midpoints k/4 + 1/8), inside
/// and on the box, and outside it: aimed through the box, or grazing along its faces and
/// voxel planes. Border and random directions; full, tiny and plane-to-plane intervals, tmin > 0.
RayBatch border_rays(const Bounds3& box, int d, size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  const std::vector<Vec3> dirs = border_directions(d);
  RayBatch out;
  const Vec3 size = box.diagonal();
  for (size_t i = 0; i < n; ++i) {
    Vec3 o;
    for (int a = 0; a < 3; ++a) {
      const int k = int(rng() % 5);
      o[a] = box.lo[a] + size[a] * (rng() % 3 == 0 && k < 4 ? 0.25f * float(k) + 0.125f : 0.25f * float(k));
    }
    Vec3 dir = rng() % 4 == 0 ? Vec3{u01(rng) - 0.5f, u01(rng) - 0.5f, u01(rng) - 0.5f} : dirs[rng() % dirs.size()];
    if (dir == Vec3{0.0f}) dir = {0.0f, 0.0f, 1.0f};
    switch (i % 5) {
      case 0:  // from outside, along the direction into the box through o
        o = o - dir * (0.5f + 2.0f * u01(rng));
        break;
      case 1: {  // outside, on the extended plane of a voxel or box face, moving within it
        const int a = int(rng() % 3);
        o[a] = box.lo[a] - size[a] * (0.25f + u01(rng));
        dir[(a + 1) % 3] = rng() % 2 ? 0.0f : dir[(a + 1) % 3];
        dir[(a + 2) % 3] = 0.0f;
        if (!(dir[a] != 0.0f)) dir[a] = 1.0f;
        dir[a] = std::fabs(dir[a]);
        break;
      }
      default:
        break;
    }
    Ray r{o, 0.0f, dir, kInfinity};
    switch (i % 7) {
      case 1: r.tmax = 1e-6f; break;
      case 2: r.tmax = 0.25f * size.x / std::max(1e-3f, length(dir)); break;
      case 3: r.tmin = 0.1f; break;
      case 4: r.tmin = 0.125f; r.tmax = 0.6f; break;
      case 5: r.tmax = 3e-8f; break;
      default: break;
    }
    out.push_back(r);
  }
  return out;
}

class ShaftsBorders : public ::testing::TestWithParam<Base> {};

// Geometry in voxel planes and rays on every border of the classification: hits and
// occlusion equal brute force for 1-4 cells per face edge (odd d: a cell centre on the face
// axis), the most culling threshold (min_prob 0: lists of leaves) and the default one, with
// and without entry boxes; most rays take a list.
TEST_P(ShaftsBorders, RaysOnVoxelAndCubeMapBordersMatchBruteForce) {
  const Base base = GetParam();
  const Scene scene = testing::scene_from_triangles(lattice(testing::small_scale() ? 150 : 400, 5));
  ASSERT_EQ(scene.bounds().lo, Vec3{0.0f});
  ASSERT_EQ(scene.bounds().hi, Vec3{1.0f});
  for (int d = 1; d <= 4; ++d) {
    const RayBatch rays = border_rays(scene.bounds(), d, testing::small_scale() ? 1500 : 4000, uint32_t(d));
    const testing::Reference ref = testing::brute_force(scene.triangles, rays);
    for (double min_prob : {0.0, -1.0})
      for (bool boxes : {false, true}) {
        ShaftConfig c;
        c.voxels = 64;
        c.dir_res = d;
        c.min_prob = min_prob;
        c.entry_boxes = boxes;
        const ShaftsAccelerator acc(scene, base, c);
        const std::string what = acc.name() + " d=" + std::to_string(d) + " min_prob=" + std::to_string(min_prob) +
                                 (boxes ? " entry boxes" : "");
        ASSERT_EQ(acc.collection().grid().res(), (std::array<int, 3>{4, 4, 4}));
        size_t listed = 0, hits = 0;
        for (size_t i = 0; i < rays.size(); ++i) {
          const Candidates cand = acc.collection().lookup(rays[i]);
          listed += !cand.list.empty() || cand.reaches_nothing;
          hits += ref.hits.prim[i] != kInvalidId;
        }
        EXPECT_GT(listed, rays.size() / 2) << what;
        EXPECT_GT(hits, rays.size() / 5) << what;
        HitBatch got;
        std::vector<uint8_t> occ;
        acc.intersect(rays, got);
        acc.occluded(rays, occ);
        const HitDiff diff = compare_hits(ref.hits, got, 0.0f);
        EXPECT_TRUE(diff.ok()) << what << ": " << diff.hit_miss << " hit/miss, " << diff.other_prim << " other; "
                               << diff.first;
        EXPECT_EQ(occ, ref.occluded) << what;
        if (HasFailure()) return;
      }
  }
}

INSTANTIATE_TEST_SUITE_P(Shafts, ShaftsBorders, ::testing::Values(Base::Binary, Base::Wide),
                         [](const auto& info) { return info.param == Base::Binary ? "binary" : "wide"; });

}  // namespace
}  // namespace rayscout
