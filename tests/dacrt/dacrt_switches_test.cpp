// Every switch combination of dacrt gives brute force's hits, closest and any, ray by ray.
#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <vector>

#include "dacrt_rays.h"
#include "generated_scenes.h"
#include "rayscout/accelerators.h"
#include "rayscout/core/hit_compare.h"
#include "rayscout/dacrt/dacrt.h"

namespace rayscout {
namespace {

using testing::TestMesh;

class DacrtSwitches : public ::testing::TestWithParam<TestMesh> {};

TEST_P(DacrtSwitches, EveryCombinationMatchesBruteForce) {
  const Scene scene = testing::scene_from_triangles(GetParam().triangles);
  const RayBatch rays = testing::nasty_rays(scene.triangles, 21);
  const auto [ref, ref_occ] = testing::brute_force(scene.triangles, rays);
  for (const auto& combo : testing::switch_combinations()) {
    for (const char* name : {"dacrt", "dacrt-rs"}) {
      auto accel = make_accelerator(name, scene, testing::options_of(combo));
      HitBatch got;
      std::vector<uint8_t> occ;
      TraceStats stats;
      accel->intersect(rays, got, &stats);
      const HitDiff d = compare_hits(ref, got, 0.0f);
      EXPECT_TRUE(d.ok()) << name << " " << testing::label_of(combo) << ": " << d.first;
      EXPECT_GT(stats.ray_box_tests, 0u);
      accel->occluded(rays, occ);
      size_t differ = 0;
      for (size_t i = 0; i < occ.size(); ++i) differ += occ[i] != ref_occ[i];
      EXPECT_EQ(occ.size(), ref_occ.size());
      EXPECT_EQ(differ, 0u) << name << " occluded, " << testing::label_of(combo);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Nasty, DacrtSwitches, ::testing::ValuesIn(testing::nasty_meshes()),
                         [](const auto& info) { return info.param.name; });

TEST(DacrtOptions, BadValuesAreInputErrors) {
  const Scene scene = testing::scene_from_triangles(testing::grid(2));
  for (const char* bad : {"cost=maybe", "order=two-rays", "skip=sometimes", "strategy=zigzag", "bins=1",
                          "bins=1000", "samples=0", "fraction=2", "delta_t=0", "C_bv=0", "sample_budget=-1", "resample=maybe",
                          "order=votes", "vote_weight=size", "unknown=1"})
    EXPECT_THROW(make_accelerator("dacrt-rs", scene, testing::options_of({bad})), InputError) << bad;
}

// A config built in code, not read from options, is checked by the constructor: 257 bins
// overran the tracer's 256-bin buffers (and wrapped its byte-sized bin indices) at the first
// trace, and 1 or 0 bins left no split candidate or clamped to [0, -1].
TEST(DacrtOptions, TheConstructorRefusesAConfigOutOfRange) {
  const Scene scene = testing::scene_from_triangles(testing::grid(2));
  const std::vector<std::function<void(DacrtConfig&)>> bad = {
      [](DacrtConfig& c) { c.bins = 257; },  [](DacrtConfig& c) { c.bins = 1; },
      [](DacrtConfig& c) { c.bins = 0; },    [](DacrtConfig& c) { c.samples = 0; },
      [](DacrtConfig& c) { c.fraction = 2; }, [](DacrtConfig& c) { c.delta_r = 0; },
      [](DacrtConfig& c) { c.delta_t = 1; }, [](DacrtConfig& c) { c.c_tri = 0; },
      [](DacrtConfig& c) { c.midpoint_ratio = std::numeric_limits<double>::quiet_NaN(); }};
  for (size_t k = 0; k < bad.size(); ++k) {
    DacrtConfig c = DacrtConfig::ray_sampled();
    bad[k](c);
    EXPECT_THROW(c.validate(), InputError) << k;
    EXPECT_THROW(DacrtAccelerator(scene.triangles, c), InputError) << k;
  }
  DacrtConfig c = DacrtConfig::ray_sampled();
  c.bins = 256;
  EXPECT_NO_THROW(DacrtAccelerator(scene.triangles, c));
}

TEST(DacrtOptions, DefaultsAreThePapersWithTheDocumentedDeviations) {
  const DacrtConfig afra = DacrtConfig::afra(), rs = DacrtConfig::ray_sampled();
  EXPECT_FALSE(afra.sampled_cost || afra.sampled_order || afra.skip_partitioning);
  EXPECT_TRUE(rs.sampled_cost && rs.sampled_order && rs.skip_partitioning);
  // rayscout's documented deviations (docs/dacrt.md): interval votes weighted by depth, the
  // sampling budget.
  EXPECT_EQ(rs.votes, DacrtVotes::Interval);
  EXPECT_TRUE(rs.depth_weighted_votes);
  EXPECT_FALSE(afra.depth_weighted_votes);
  EXPECT_DOUBLE_EQ(rs.sample_budget, 1.0);
  EXPECT_EQ(afra.sample_budget, 0.0);
  EXPECT_FALSE(rs.resample_second);
  EXPECT_EQ(rs.samples, 100);
  EXPECT_EQ(rs.min_rays_sampling, 1000u);
  EXPECT_EQ(rs.bins, 32);
  EXPECT_EQ(rs.delta_r, 8u);
  EXPECT_EQ(rs.delta_t, 8u);
  EXPECT_DOUBLE_EQ(rs.midpoint_ratio, 1.5);
  // Eq. (6): an inner child (>= delta_t triangles) is skipped when alpha > 0.5, whatever C_bv.
  EXPECT_DOUBLE_EQ(rs.skip_threshold(8), 0.5);
  EXPECT_DOUBLE_EQ(rs.skip_threshold(100000), 0.5);
  // Eq. (5) for a leaf child of n triangles: 1 - C_bv / (C_tri n) = 1 - 1 / (2 n).
  EXPECT_DOUBLE_EQ(rs.skip_threshold(1), 0.5);
  EXPECT_DOUBLE_EQ(rs.skip_threshold(4), 0.875);
  EXPECT_DOUBLE_EQ(rs.skip_threshold(7), 1.0 - 1.0 / 14.0);
  DacrtConfig c = rs;
  c.c_bv = 3.0;
  EXPECT_DOUBLE_EQ(c.skip_threshold(4), 1.0 - 3.0 / 8.0);
  EXPECT_DOUBLE_EQ(c.skip_threshold(8), 0.5);
  EXPECT_EQ(rs.sample_count(5000), 100u);
  DacrtConfig f = rs;
  f.fraction = 0.001;
  EXPECT_EQ(f.sample_count(2'000'000), 2000u);
  EXPECT_EQ(f.sample_count(10), 1u);
}

}  // namespace
}  // namespace rayscout
