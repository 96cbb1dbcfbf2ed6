// DacrtConfig: every switch and constant of divide-and-conquer ray tracing (Afra 2012 and
// the ray-sampled method of Nabata et al., IPSJ Journal 2014).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "rayscout/core/accelerator_options.h"

namespace rayscout {

/// How sample rays are drawn from a node's ray set (sec. 4.1, fig. 9).
enum class DacrtSampling { Stride, Random };

/// Vote rule of the sampled child order (sec. 4.3), see DacrtConfig::votes.
enum class DacrtVotes { Entry, Sign, Interval, Literal };

/// Tunables of DacrtAccelerator. The defaults give Afra's DACRT; ray_sampled() switches on the
/// three contributions of the ray-sampling paper. Cost constants are relative (one ray-box test = 1).
struct DacrtConfig {
  /// Split cost, eq. (2) with sampled hit ratios alpha (true) or eq. (1) with
  /// surface-area ratios (false, Afra). Option cost=sampled|sah.
  bool sampled_cost = false;
  /// Child order by the sample rays' n_L/n_R votes (true, sec. 4.3) or by the direction of
  /// one ray along the split axis (false, Afra). Option order=one-ray (false) or the name of
  /// a vote rule (true, see votes).
  bool sampled_order = false;
  /// With sampled_order, how the sample rays vote (docs/dacrt.md). Literal = Algorithm 2,
  /// lines 10-14 as printed: every sample ray votes, n_L when d_L < d_R with d = inf on a
  /// miss, else n_R (so rays missing both, or entering both at once, vote R). The others
  /// count only rays that hit both children: Entry = the nearer box entry (equal entries by
  /// the ray's direction), Sign = the ray's direction along the split axis, Interval = only
  /// when one box's [entry, exit] interval ends before the other begins (the ray surely
  /// meets that child's triangles first).
  /// Option order=sampled|literal-votes|sign-votes|interval-votes.
  DacrtVotes votes = DacrtVotes::Entry;
  /// With sampled_order: weigh each child's votes by the depth of the other child,
  /// log2(|T| + 1) (true), or compare n_L with n_R (false, Algorithm 1 line 18). A ray that
  /// meets one child first but is sent into the other first crosses that other subtree in
  /// vain, so the order with the least expected waste puts L first when
  /// n_L log2(|T_R| + 1) >= n_R log2(|T_L| + 1) (docs/dacrt.md). Option vote_weight=depth|none.
  bool depth_weighted_votes = false;
  /// With skip_partitioning: alpha of the child visited second is measured again with the
  /// sample rays' hit distances after the first child (what its partitioning would see), not
  /// before it. Option resample=on|off.
  bool resample_second = false;
  /// Skip partitioning the rays against a child when alpha > 1 - C_bv / (C_child n_child),
  /// eq. (5) (sec. 4.4). Option skip=on|off.
  bool skip_partitioning = false;

  /// Sample rays at a fixed stride through the node's ray array or at random positions.
  /// Option strategy=stride|random.
  DacrtSampling strategy = DacrtSampling::Stride;
  /// N_s, sample rays per node (paper: 100). Option samples=N.
  int samples = 100;
  /// When > 0, N_s = max(1, fraction |R|) instead of `samples` (fig. 9: 0.001, 0.01).
  /// Option fraction=F.
  double fraction = 0.0;
  /// Nodes with fewer rays do not sample and behave exactly like Afra's DACRT (paper: 1000).
  /// Option min_rays=N.
  size_t min_rays_sampling = 1000;
  /// With sampled_cost: eq. (2) is evaluated over the K - 1 candidates only when their
  /// N_s 2 (K - 1) sample-ray tests are at most sample_budget times the node's own partition
  /// tests 2 |R|, i.e. N_s (K - 1) <= sample_budget |R|. Other sampled nodes keep the SAH
  /// split of eq. (1) and test the sample rays against the two chosen children only (order
  /// and skipping), as the paper does below its midpoint ratio. 0 = always (the paper);
  /// dacrt-rs: 1. Option sample_budget=X.
  double sample_budget = 0.0;
  /// Seed of the random strategy (results never depend on it, only the speed). Option seed=N.
  uint64_t seed = 1;

  /// delta_R: a node with fewer rays tests all pairs (Algorithm 1, line 2). Option delta_r=N.
  size_t delta_r = 8;
  /// delta_T: a node with fewer triangles tests all pairs. Option delta_t=N.
  size_t delta_t = 8;
  /// K, bins over the widest axis of the centroid bounds (K - 1 split candidates, Wald 2007).
  /// Option bins=K, 2..256.
  int bins = 32;
  /// Split at the midpoint of the widest centroid axis when |R| / |T| <= this (sec. 5:
  /// "1.5 in the current implementation"). Option midpoint_ratio=X.
  double midpoint_ratio = 1.5;

  // C_T and C_I of eqs. (1), (2) are not options: the split cost is only ever minimised over
  // the bins, never compared with a leaf's, so a constant and a positive factor cannot change
  // the chosen split.
  /// C_bv of eqs. (3)-(5): cost of one ray-box test when deciding to skip. Option C_bv=X.
  double c_bv = 1.0;
  /// C_child for a child that will be a leaf (one ray-triangle test) in eq. (5); an inner
  /// child uses C_child = C_bv and n_child = 2, i.e. eq. (6) alpha > 0.5. Option C_tri=X.
  double c_tri = 2.0;

  /// Trace with all cores: the batch is cut into one contiguous ray range per thread
  /// (tbb::global_control's limit), each solved by its own DACRT as a task. Hits do not
  /// depend on the thread count; work counts do (each range splits on its own rays). Off =
  /// one thread, as in the paper. Option parallel=on|off.
  bool parallel = true;

  /// Afra's DACRT (all three contributions off).
  static DacrtConfig afra() { return {}; }
  /// `dacrt-rs`: the three contributions of Algorithm 1 on, with rayscout's documented
  /// deviations (docs/dacrt.md): interval votes weighed by depth instead of Algorithm 2's
  /// literal rule and line 18's majority, and the sampling budget. The paper's literal
  /// configuration is afra() with cost=sampled, order=literal-votes, skip=on.
  static DacrtConfig ray_sampled() {
    DacrtConfig c;
    c.sampled_cost = c.sampled_order = c.skip_partitioning = true;
    c.votes = DacrtVotes::Interval;
    c.depth_weighted_votes = true;
    c.sample_budget = 1.0;
    return c;
  }
  /// True when any contribution needs sample rays.
  bool samples_rays() const { return sampled_cost || sampled_order || skip_partitioning; }
  /// Sample count N_s for a node of n rays.
  size_t sample_count(size_t n) const;
  /// Eq. (5): a child of `child_tris` triangles is entered without partitioning its rays when
  /// its sampled alpha exceeds 1 - C_bv / (C_child n_child). A child that will be a leaf
  /// (< delta_t triangles) has C_child = C_tri, n_child = child_tris; an inner child has
  /// C_child = C_bv, n_child = 2, i.e. eq. (6): alpha > 0.5.
  double skip_threshold(size_t child_tris) const;
  /// Throws InputError naming the first value out of range (bins in [2, 256], samples >= 1,
  /// fraction in [0, 1], delta_r >= 1, delta_t >= 2, sample_budget and midpoint_ratio >= 0,
  /// C_bv and C_tri > 0): from_options and DacrtAccelerator's constructor both check with it,
  /// so that a config built in code cannot overrun the tracer's 256-bin buffers.
  void validate() const;
  /// Reads the keys above from options over `defaults`; throws InputError on bad values.
  static DacrtConfig from_options(const AcceleratorOptions& options, DacrtConfig defaults);
  /// One line naming every setting, for benchmark logs.
  std::string describe() const;
  /// The value of option `order` that selects this child-order rule.
  std::string order_name() const;
};

}  // namespace rayscout
