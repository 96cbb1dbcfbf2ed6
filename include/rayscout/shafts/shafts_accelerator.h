// ShaftsAccelerator: ray classification over a BVH; registry "shafts" (Bvh2) and "shafts-wide".
#pragma once

#include <span>

#include "rayscout/bvh/bvh2.h"
#include "rayscout/bvh/bvh_build_config.h"
#include "rayscout/bvh/wide_bvh.h"
#include "rayscout/core/accelerator.h"
#include "rayscout/scene/scene.h"
#include "rayscout/shafts/shaft_collection.h"
#include "rayscout/shafts/shaft_config.h"

namespace rayscout {

/// Ray classification for accelerated BVH traversal (Hendrich, Pospisil, Meister, Bittner,
/// EGSR 2019): builds a BVH, then a ShaftCollection over it; a ray is classified into its
/// shaft, the shaft's candidate list seeds the BVH's normal traversal (sec. 4.5). Rays
/// without a shaft or in a shaft without a list start at the root; rays of a shaft that
/// provably reaches no geometry miss without traversal. Hits are those of the BVH traversed
/// from the root, so bit-identical to brute but for the grazing rays of docs/bvh.md.
class ShaftsAccelerator final : public Accelerator {
 public:
  enum class Base { Binary, Wide };
  /// Builds over scene.triangles (the scene must outlive the accelerator; its camera and
  /// lights feed the select=camera and camera-voxels pre-pass).
  ShaftsAccelerator(const Scene& scene, Base base, const ShaftConfig& config = {},
                    const BvhBuildConfig& bvh_config = {});

  /// The shaft and BVH build settings `shafts` (Binary) or `shafts-wide` (Wide) read from
  /// --accel-opt keys: the wide BVH is built as the "bvh" accelerator builds it. Keys neither
  /// reads stay unread, for AcceleratorOptions::check_all_used().
  struct Settings {
    ShaftConfig shafts;
    BvhBuildConfig bvh;
  };
  static Settings settings_from_options(const AcceleratorOptions& options, Base base);

  std::string name() const override { return base_ == Base::Binary ? "shafts" : "shafts-wide"; }
  /// BVH + collection build time and memory.
  BuildInfo build_info() const override { return info_; }

  using Accelerator::intersect;
  using Accelerator::occluded;
  /// use_lists = false traces the very same BVH from the root: the side-by-side baseline.
  /// Irregular rays are handled as by Accelerator::intersect and occluded.
  void intersect(const RayBatch& rays, HitBatch& hits, TraceStats* stats, bool use_lists) const;
  void occluded(const RayBatch& rays, std::vector<uint8_t>& occluded, TraceStats* stats,
                bool use_lists) const;

  const ShaftCollection& collection() const { return collection_; }
  /// Collection figures (build time, memory, list lengths).
  const ShaftStats& collection_stats() const { return collection_.stats(); }
  double bvh_build_ms() const { return bvh_build_ms_; }
  /// The BVH's whole memory (a Bvh2 with its triangle copy).
  size_t bvh_memory_bytes() const;
  const Bvh2& bvh2() const { return bvh2_; }
  const WideBvh& wide_bvh() const { return wide_; }

 private:
  void intersect_batch(const RayBatch& rays, HitBatch& hits, TraceStats* stats) const override;
  void occluded_batch(const RayBatch& rays, std::vector<uint8_t>& occluded, TraceStats* stats) const override;
  /// The batch loops behind both, on rays the base class has made regular.
  void trace_batch(const RayBatch& rays, HitBatch& hits, TraceStats* stats, bool use_lists) const;
  void trace_batch(const RayBatch& rays, std::vector<uint8_t>& occluded, TraceStats* stats, bool use_lists) const;

  Base base_;
  Bvh2 bvh2_;
  WideBvh wide_;
  ShaftCollection collection_;
  double bvh_build_ms_ = 0.0;
  BuildInfo info_;
};

}  // namespace rayscout
