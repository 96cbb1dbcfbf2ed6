// DacrtAccelerator: divide-and-conquer ray tracing without a stored hierarchy (Afra 2012;
// ray-sampled variant of Nabata, Iwasaki, Dobashi, Nishita, IPSJ Journal 2014, Algorithms 1, 2).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "rayscout/core/accelerator.h"
#include "rayscout/dacrt/dacrt_config.h"

namespace rayscout {

/// Work of the last trace call beyond TraceStats, filled only when stats were requested.
struct DacrtStats {
  uint64_t partition_box_tests = 0;  ///< ray-box tests of ray-set partitioning (without the sample rays')
  uint64_t sampling_box_tests = 0;   ///< ray-box tests of the sample rays (Algorithm 2)
  uint64_t skipped_partitions = 0;   ///< children entered with the unfiltered ray set (eq. 5)
  uint64_t sampled_nodes = 0;        ///< nodes that drew sample rays
  uint64_t leaves = 0;               ///< NaiveRT calls

  DacrtStats& operator+=(const DacrtStats& o) {
    partition_box_tests += o.partition_box_tests; sampling_box_tests += o.sampling_box_tests;
    skipped_partitions += o.skipped_partitions; sampled_nodes += o.sampled_nodes; leaves += o.leaves;
    return *this;
  }
};

/// DACRT over a fixed triangle set. Nothing is built: every trace call recursively splits
/// (rays, triangles) with index arrays partitioned in place, taken from an arena kept between
/// calls, with a size that depends only on |R| and |T| (and the task count in parallel mode).
class DacrtAccelerator final : public Accelerator {
 public:
  /// Keeps a view of triangles (they must outlive the accelerator). name: registry name.
  /// Throws InputError for a config out of range (DacrtConfig::validate).
  DacrtAccelerator(std::span<const Triangle> triangles, const DacrtConfig& config,
                   std::string name = "dacrt");
  ~DacrtAccelerator() override;

  std::string name() const override { return name_; }
  BuildInfo build_info() const override { return {}; }
  /// Scratch bytes the last trace call took, counted as it allocates them (the formula is
  /// scratch_bytes(|R|, |T|, tasks)). With concurrent calls, of the one that finished last
  /// (here and in last_stats).
  size_t last_trace_memory_bytes() const override;
  /// Counts of the last call that passed non-null stats.
  DacrtStats last_stats() const;
  const DacrtConfig& config() const { return config_; }

  /// Scratch bytes a call with n_rays and n_triangles allocates, with `tasks` ray ranges.
  static size_t scratch_bytes(size_t n_rays, size_t n_triangles, size_t tasks);

 private:
  void intersect_batch(const RayBatch& rays, HitBatch& hits, TraceStats* stats) const override;
  void occluded_batch(const RayBatch& rays, std::vector<uint8_t>& occluded, TraceStats* stats) const override;

  template <bool kOccluded>
  void trace(const RayBatch& rays, HitBatch* hits, std::vector<uint8_t>* occluded, TraceStats* stats) const;

  std::span<const Triangle> triangles_;
  DacrtConfig config_;
  std::string name_;
  /// Per-call buffers kept between calls (grown to the largest call, never initialised
  /// beyond what a call writes), so repeated batches do not page-fault fresh memory; the
  /// triangle boxes and their bounds are computed at the first call. A concurrent call that
  /// finds it in use allocates its own.
  struct Arena;
  mutable std::unique_ptr<Arena> arena_;
  mutable std::mutex arena_mutex_;
  mutable std::mutex last_mutex_;  ///< guards the two reports below (calls may run concurrently)
  mutable size_t last_memory_ = 0;
  mutable DacrtStats last_stats_;
};

}  // namespace rayscout
