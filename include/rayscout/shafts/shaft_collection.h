// ShaftCollection: candidate lists of BVH nodes per shaft, the lookup that seeds traversal.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "rayscout/core/ray.h"
#include "rayscout/core/triangle.h"
#include "rayscout/shafts/shaft_config.h"
#include "rayscout/shafts/shaft_grid.h"
#include "rayscout/shafts/tree_view.h"

namespace rayscout {

namespace detail {
struct VoxelLists;     // one voxel's lists before packing (src/shafts/voxel_lists.h)
class EntryBoxCodec;   // quantisation of the entry boxes (src/shafts/entry_box_codec.h)
}  // namespace detail

/// Build and memory figures of a collection (paper sec. 5 reports the same).
struct ShaftStats {
  double build_ms = 0.0;             ///< collection only (all budget iterations), BVH excluded
  int build_rounds = 0;              ///< builds needed to meet the memory budget
  double pilot_ms = 0.0;             ///< wall: the budget's pilot search before the first round
  // "Last round" below: the round whose collection is kept, the first when a finer second
  // round went over the budget.
  double select_ms = 0.0;            ///< last round, wall: choosing the listed voxels / shafts
  double lists_ms = 0.0;             ///< last round, wall: sample rays and Algorithm 1
  double samples_ms = 0.0;           ///< last round: tracing the sample rays (traced per chunk: summed over threads, may exceed lists_ms)
  double pack_ms = 0.0;              ///< last round, wall: deduplication and packing
  size_t traced_samples = 0;         ///< sample rays traced when reuse_rays shares them (else 0)
  std::array<int, 3> res{};          ///< voxels per axis
  int dir_res = 0;
  size_t voxels = 0, listed_voxels = 0;  ///< all voxels; voxels with a shaft table
  size_t shafts = 0, listed_shafts = 0;  ///< all shafts; shafts with a list (incl. empty ones)
  size_t empty_lists = 0;            ///< shafts proven to reach no geometry (rays return a miss)
  size_t near_retries = 0;           ///< list rebuilds with clamped sample distances (ShaftConfig::near_retries)
  size_t overflow_retries = 0;       ///< list rebuilds with a raised threshold
  size_t overflow_fallbacks = 0;     ///< lists that stayed too long: cullNodeSubtree(root)
  size_t unique_lists = 0;
  size_t lookup_bytes = 0;           ///< voxel table + shaft entry table
  size_t list_bytes = 0;             ///< list area after deduplication (ids + entry boxes)
  size_t dedup_saved_bytes = 0;      ///< list bytes deduplication did not store
  size_t budget_bytes = 0;
  double mean_list = 0.0;            ///< mean length over non-empty listed shafts
  int max_list = 0;
  std::vector<size_t> length_histogram;  ///< [len] = shafts with a list of that length
  size_t memory_bytes() const { return lookup_bytes + list_bytes; }
  /// Multi-line human-readable summary.
  std::string summary() const;
};

/// What a lookup gives: a candidate list (empty = start at the root) or reaches_nothing.
struct Candidates {
  std::span<const uint32_t> list;
  /// Boxes of the list entries (collections built with entry_boxes), quantised outward to
  /// 1/255 of the grid box per axis (ShaftCollection::entry_codec()) and laid out per list as
  /// 6 byte rows: lo.x of every entry, then lo.y, lo.z, hi.x, hi.y, hi.z. At least 8 readable
  /// bytes follow every row (SIMD loads).
  const uint8_t* boxes = nullptr;
  bool reaches_nothing = false;  ///< the shaft provably reaches no geometry: the ray misses
};

/// The collection (paper sec. 4.1, fig. 4): a per-voxel table (base index into the entry
/// table, or none), per listed voxel 6 d^2 packed entries (offset << 5 | length; 0 = no
/// list), and one concatenated area of 4-byte node references. Identical lists share storage.
class ShaftCollection {
 public:
  static constexpr uint32_t kNoVoxel = 0xFFFFFFFFu;    ///< voxel table: the voxel has no entries
  static constexpr uint32_t kEmptyList = 0xFFFFFFE0u;  ///< entry: reaches nothing (length 0, offset all ones)

  /// Traces a ray from the root to its closest hit t (infinity on a miss); must be thread-safe.
  using TraceFn = std::function<float(const Ray&)>;

  /// Builds over tree (the lists hold tree.ref values) for the scene box `box`; the grid's
  /// resolution comes from config.voxels or the budget (budget_rel times bvh_bytes, or
  /// budget_mib). trace gives a sample ray's closest hit distance; sample_rays (may be empty)
  /// are the pre-pass rays for select=camera and camera-voxels. Parallel (oneTBB); same
  /// result for any thread count.
  static ShaftCollection build(const TreeView& tree, const Bounds3& box, size_t bvh_bytes,
                               std::span<const Triangle> tris, const TraceFn& trace,
                               const RayBatch& sample_rays, const ShaftConfig& config);

  /// The ray's candidates (traversal, paper sec. 4.5).
  Candidates lookup(const Ray& ray) const {
    ShaftCoord c;
    if (!grid_.classify(ray, c)) return {};
    return lookup(c);
  }
  /// The candidates of a classified shaft.
  Candidates lookup(ShaftCoord c) const {
    const uint32_t base = voxel_base_[c.voxel];
    if (base == kNoVoxel) return {};
    const uint32_t e = entries_[base + c.cell];
    if (e == kEmptyList) return {{}, nullptr, true};
    const uint32_t* ids = lists_.data() + (e >> 5);
    const uint32_t len = e & 31u;
    return {{ids, len}, entry_codec_ ? reinterpret_cast<const uint8_t*>(ids + len) : nullptr, false};
  }
  /// Where the entry of a classified shaft lives (nullptr: its voxel has no table); for
  /// prefetching ahead of lookup(c).
  const uint32_t* entry_address(ShaftCoord c) const {
    const uint32_t base = voxel_base_[c.voxel];
    return base == kNoVoxel ? nullptr : entries_.data() + base + c.cell;
  }
  const ShaftGrid& grid() const { return grid_; }
  /// Encoder and decoder of the entry boxes (src/shafts/entry_box_codec.h), over the grid
  /// box; nullptr for a collection built without entry_boxes.
  const detail::EntryBoxCodec* entry_codec() const { return entry_codec_.get(); }
  const ShaftStats& stats() const { return stats_; }
  size_t memory_bytes() const { return stats_.memory_bytes(); }

 private:
  /// Builds for a fixed grid (build() without the budget search; config.voxels > 0 gives
  /// such a build too).
  static ShaftCollection build_grid(const TreeView& tree, const ShaftGrid& grid,
                                    std::span<const Triangle> tris, const TraceFn& trace,
                                    const RayBatch& sample_rays, const ShaftConfig& config);
  /// Packs lists[i], the lists of voxel listed[i] (serial, so offsets do not depend on the
  /// thread count): lookup tables, deduplicated list area, entry boxes, and the figures in
  /// stats_.
  void pack(const TreeView& tree, const std::vector<uint32_t>& listed, const std::vector<detail::VoxelLists>& lists,
            bool dedup);

  ShaftGrid grid_;
  /// Shared by copies (it never changes after the build); a pointer, so that the codec's
  /// type stays private to src/shafts.
  std::shared_ptr<const detail::EntryBoxCodec> entry_codec_;
  std::vector<uint32_t> voxel_base_;
  std::vector<uint32_t> entries_;
  /// The list area: per unique list its node references, then (with entry boxes) its
  /// entry-box rows (6 len bytes, padded to 4; layout: Candidates::boxes), so a lookup
  /// touches one region.
  std::vector<uint32_t> lists_;
  ShaftStats stats_;
};

}  // namespace rayscout
