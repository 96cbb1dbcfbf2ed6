// ShaftConfig: the tunables of a shaft collection (ray classification, Hendrich et al. 2019).
#pragma once

#include <optional>

#include "rayscout/core/accelerator_options.h"

namespace rayscout {

/// Which shafts get candidate lists (the option key `select`).
enum class ShaftSelect {
  Occupied,  ///< "occupied": every direction of each voxel holding geometry
  Camera,    ///< "camera": the most used shafts of a ray-sampling pre-pass (paper sec. 4.4)
  /// "camera-voxels": every direction of the voxels the pre-pass rays start in most often
  /// (ours: the pre-pass decides where, not in which direction, so sparse bounces suffice)
  CameraVoxels,
};

/// Where sample rays start in their voxel (the option key `origins`).
enum class SampleOrigins {
  Volume,   ///< "volume": uniform in the voxel (paper sec. 4.3)
  Surface,  ///< "surface": uniform by area on the triangles inside the voxel, where secondary
            ///< rays start (ours); voxels without surface fall back to volume
};

/// Tunables of a shaft collection. Defaults follow the authors' reference implementation
/// (PBRT-v3 fork, branch frustum_shafts) where it has one; see docs/shafts.md.
struct ShaftConfig {
  /// Absolute memory budget of the collection in MiB (lookup tables + list area); 0 = use
  /// budget_rel. The spatial resolution is derived from the budget (paper sec. 4.1).
  double budget_mib = 0.0;
  /// Budget relative to the memory of the tree the lists point into (used when budget_mib = 0):
  /// Bvh2 nodes and ids without its triangle copy, or the whole WideBvh.
  double budget_rel = 1.0;
  /// Total voxel count; > 0 overrides the budget (sweeps). Voxels are kept near-cubical.
  long voxels = 0;
  /// Direction cells per cube-map face edge: 6 d^2 direction cells per voxel.
  int dir_res = 4;
  /// Random sample rays per shaft for hitProbability (paper sec. 4.3: 20). Unset (default) =
  /// 4 for shafts, 3 for shafts-wide: stratified, they save as many or more steps than 8
  /// independent ones on Sibenik, Sponza and Conference, and build faster (docs/shafts.md,
  /// Options; docs/history/shafts.md). With the wide threshold 7/8 both 3 and 4 mean "all
  /// sample rays enter the box".
  std::optional<int> samples;
  /// Latin-hypercube sample rays: each of the 5 dimensions (origin x, y, z; direction u, v)
  /// is split into `samples` strata, one sample per stratum (random pairing); off = independent
  /// uniform samples.
  bool stratified = true;
  /// Where the sample rays start (see SampleOrigins).
  SampleOrigins origins = SampleOrigins::Volume;
  /// Share sample rays along their paths: a traced sample ray also serves every later listed
  /// voxel it crosses before its hit (same direction cell), so ~3x fewer rays are traced.
  /// Unset (default) = on for shafts-wide (same steps saved, build ~15 % faster), off for
  /// shafts (there it saves 1-3 points fewer steps).
  std::optional<bool> reuse_rays;
  /// Expand a node when its hit probability is >= this; < 0 = (k-1)/k for a k-ary BVH.
  double min_prob = -1.0;
  /// Maximum candidate list length (at most 31: the length is packed into 5 bits).
  int max_list = 31;
  /// On overflow the list is first rebuilt with its sample rays' hit distances clamped to
  /// 4, 2, 1, 1/2, ... voxel diagonals, near_retries times (ours, not the paper's): nodes far
  /// from the voxel, which fewer of the shaft's rays reach, stop being expanded before the
  /// list gives up depth near the voxel, which all of them cross. 0 = raised thresholds only.
  int near_retries = 5;
  /// Then the threshold becomes min_prob + (i+1)/20 for i < retries (distances still
  /// clamped; the reference implementation's step, sec. 4.3 only says "raised gradually");
  /// a raise needing as many sample hits as the previous build is skipped (the same lists);
  /// after that the list is the single node cullNodeSubtree(root) (ours).
  int retries = 10;
  /// Which shafts get lists; Camera and CameraVoxels sample from scene.camera.
  ShaftSelect select = ShaftSelect::Occupied;
  /// Camera, CameraVoxels: fraction of the pre-pass rays whose shafts (voxels) get lists.
  double coverage = 0.95;
  /// Camera, CameraVoxels: pre-pass image width in pixels (height from a 4:3 aspect); 1 sample per pixel,
  /// plus two cosine diffuse bounces and a shadow ray to each of the first 4 point lights at each hit.
  int prepass_width = 96;
  /// Trace the sample rays with a temporary 8-wide BVH collapsed from the binary one (same
  /// hits, faster); off = trace them with the binary BVH.
  bool wide_sampling = true;
  /// Store a 6-byte quantised box per list entry; the traversal then box-tests the entries,
  /// drops the missed ones and seeds one traversal with the rest (nearest first for a closest
  /// hit). Needed for the wide BVH, whose start entries are entered without a box test.
  /// Unset (default) = on for shafts-wide, off for shafts (Bvh2 tests its start entries itself).
  std::optional<bool> entry_boxes;
  /// shafts (Bvh2): Algorithm 1 walks the Bvh2 collapsed by this many levels per step (1 =
  /// the binary tree itself; 2 = 4-ary, 3 = 8-ary view of the same nodes), 1..4.
  int walk_levels = 1;
  /// Store identical lists once (paper sec. 4.4); off = every list on its own, to measure what
  /// deduplication saves.
  bool dedup = true;
  /// Seed of the sample rays (the result is the same for any thread count).
  unsigned seed = 1;

  /// The unset (automatic) values filled in for a BVH of the given arity (2 = Bvh2): samples,
  /// reuse_rays, entry_boxes, min_prob. Validates first, so that every builder checks the config it
  /// was handed.
  ShaftConfig resolved(int arity) const;
  /// Throws InputError naming the first value out of range: the one place of the rules.
  void validate() const;
  /// Reads the keys above from options (--accel-opt key=value) for a BVH of the given arity
  /// (2 = Bvh2; "auto" or a left-out key leaves samples, reuse_rays and entry_boxes unset);
  /// the Bvh2-only keys walk_levels and wide_sampling are left unread otherwise, so that
  /// check_all_used() reports them. Throws InputError on a bad value (validate()).
  static ShaftConfig from_options(const AcceleratorOptions& options, int arity);
};

}  // namespace rayscout
