// The BVH accelerators: "bvh2" (binary, scalar traversal) and "bvh" (8-wide, SIMD traversal).
#pragma once

#include <span>

#include "rayscout/bvh/bvh2.h"
#include "rayscout/bvh/bvh_build_config.h"
#include "rayscout/bvh/wide_bvh.h"
#include "rayscout/core/accelerator.h"
#include "rayscout/core/accelerator_options.h"

namespace rayscout {

/// Reads the binary build's tunables from accelerator options: bins, max_leaf_size,
/// traversal_cost, intersection_cost, leaf_block, presplit, presplit_pieces (defaults from
/// `defaults`); throws InputError for values out of range.
BvhBuildConfig bvh_config_from_options(const AcceleratorOptions& options, const BvhBuildConfig& defaults = {});
/// The same from wide_bvh_default_config(), plus the 8-wide collapse's keys: collapse
/// (greedy|sah), collapse_node_cost, collapse_leaf_cost, collapse_block_cost,
/// collapse_max_leaf. Only the accelerators that collapse read them, so that a collapse key
/// given to `bvh2` or `shafts` is reported as unused, not silently ignored.
BvhBuildConfig wide_bvh_config_from_options(const AcceleratorOptions& options);

/// The build the "bvh" accelerator uses by default: leaves of up to 8 triangles costed per
/// 4-triangle block, and 10 % pre-split references of at most 2 pieces per triangle (budget
/// honored by bisection). With up to 65 pieces, 5 % cost Conference 15-20 % of its primary and
/// diffuse throughput against no pre-splitting; with 2 pieces, 8-12 % help Sponza (shadow rays
/// +20 %) and leave Sibenik and Conference within a few % of no pre-splitting. The Bvh2 is
/// collapsed into 8-wide nodes by SAH cost (collapse=sah, Ylitie et al. 2017); against the
/// greedy collapse: diffuse rays +5-7 %, primary +4-14 %, shadow +2-15 %, AO 0-9 %
/// (docs/performance.md, Core engine).
BvhBuildConfig wide_bvh_default_config();

/// Registry "bvh2": a binned SAH Bvh2, one ray at a time, rays in parallel (oneTBB).
class Bvh2Accelerator final : public Accelerator {
 public:
  /// Builds over triangles (the Bvh2 keeps its own copy).
  explicit Bvh2Accelerator(std::span<const Triangle> triangles, const BvhBuildConfig& config = {});
  std::string name() const override { return "bvh2"; }
  BuildInfo build_info() const override { return info_; }
  const Bvh2& bvh() const { return bvh_; }

 private:
  void intersect_batch(const RayBatch& rays, HitBatch& hits, TraceStats* stats) const override;
  void occluded_batch(const RayBatch& rays, std::vector<uint8_t>& occluded, TraceStats* stats) const override;

  Bvh2 bvh_;
  BuildInfo info_;
};

/// Registry "bvh": the 8-wide WideBvh with SIMD box tests, rays in parallel (oneTBB).
class WideBvhAccelerator final : public Accelerator {
 public:
  /// Builds over triangles (copied into leaf order; they need not outlive it).
  explicit WideBvhAccelerator(std::span<const Triangle> triangles,
                              const BvhBuildConfig& config = wide_bvh_default_config());
  std::string name() const override { return "bvh"; }
  BuildInfo build_info() const override { return info_; }
  const WideBvh& bvh() const { return bvh_; }

 private:
  void intersect_batch(const RayBatch& rays, HitBatch& hits, TraceStats* stats) const override;
  void occluded_batch(const RayBatch& rays, std::vector<uint8_t>& occluded, TraceStats* stats) const override;

  WideBvh bvh_;
  BuildInfo info_;
};

}  // namespace rayscout
