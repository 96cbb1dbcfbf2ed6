// ShaftCollection::build: the memory budget decides the grid resolution. Pilots of a few
// shafts predict the memory of candidate grids; then the one real build (build_grid) runs.
#include "rayscout/shafts/shaft_collection.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include <tbb/parallel_for.h>

#include "group_list_builder.h"
#include "rayscout/core/stopwatch.h"
#include "shaft_samples.h"
#include "shaft_selection.h"

namespace rayscout {

namespace {

using detail::Selection;

/// The budget search stays below the 2^32 shafts a collection can address.
constexpr double kMaxShafts = 0.9 * 4294967296.0;

/// Builds the list (node indices) of one shaft on its own (budget pilots): Algorithm 1 (a
/// group of one), the build's overflow policy (retry_overflow; it may clamp samples'
/// distances), then the cullNodeSubtree(root) fallback.
void build_one(const TreeView& tree, const ShaftGrid& grid, ShaftCoord coord, const ShaftCollection::TraceFn& trace,
               const detail::VoxelSurfaces* surfaces, const ShaftConfig& config, detail::ShaftSamples& samples,
               detail::GroupListBuilder::Scratch& scratch, std::vector<uint32_t>& list) {
  list.clear();
  if (tree.size() == 0) return;
  const Shaft shaft(grid, coord);
  samples.resize(size_t(config.samples.value()));
  detail::trace_own_samples(shaft.voxel(), shaft.cell(), uint64_t(coord.voxel) * grid.cells_per_voxel() + coord.cell,
                            surfaces, coord.voxel, trace, config, [&](size_t s, const Ray& ray, float hit_t) {
                              detail::store_sample(samples, s, ray.org, ray.dir, hit_t);
                            });
  const Shaft* const member = &shaft;
  detail::GroupListBuilder builder(tree, shaft, {&member, 1}, samples, config.samples.value(), scratch);
  auto fits = [&](double min_prob) { return builder.build(min_prob, config.max_list, 1, &list) == 1; };
  const bool ok = fits(config.min_prob) ||
                  detail::retry_overflow(
                      config.near_retries, config.retries, config.min_prob, config.samples.value(),
                      length(shaft.voxel().diagonal()),
                      [&](double p, bool) { return fits(p); }, [&](float reach) { samples.clamp_hits(reach); });
  if (!ok) builder.fallback(1, &list);
}

/// What every grid of the budget search is built from (ShaftCollection::build's arguments).
struct BuildInputs {
  const TreeView& tree;
  const Bounds3& box;
  std::span<const Triangle> tris;
  const ShaftCollection::TraceFn& trace;
  const RayBatch& sample_rays;
  const ShaftConfig& config;  ///< resolved
};

/// The ids (voxel * cells + cell) of the shafts a grid's selection lists, in id order.
std::vector<uint64_t> selected_shafts(const ShaftGrid& grid, const Selection& sel) {
  std::vector<uint64_t> ids;
  for (uint32_t v = 0; v < grid.voxel_count(); ++v) {
    if (!sel.voxel_listed[v]) continue;
    for (uint32_t c = 0; c < grid.cells_per_voxel(); ++c) {
      const uint64_t id = uint64_t(v) * grid.cells_per_voxel() + c;
      if (sel.shaft_selected.empty() || sel.shaft_selected[id]) ids.push_back(id);
    }
  }
  return ids;
}

/// Mean list length of up to 192 pilot shafts taken at an even stride from ids, each built on
/// its own (build_one).
double mean_pilot_length(const BuildInputs& in, const ShaftGrid& grid, const std::vector<uint64_t>& ids) {
  const uint32_t cells = grid.cells_per_voxel();
  const size_t pilots = std::min<size_t>(192, ids.size());
  if (pilots == 0) return 0.0;
  auto pilot = [&](size_t i) { return ids[i * ids.size() / pilots]; };
  std::optional<detail::VoxelSurfaces> surfaces;
  if (in.config.origins == SampleOrigins::Surface && in.tree.size() > 0) {
    std::vector<uint32_t> voxels;
    for (size_t i = 0; i < pilots; ++i) voxels.push_back(uint32_t(pilot(i) / cells));
    voxels.erase(std::unique(voxels.begin(), voxels.end()), voxels.end());
    surfaces.emplace(grid, in.tris, voxels);
  }
  std::vector<size_t> lengths(pilots, 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, pilots, 8), [&](const auto& range) {
    detail::ShaftSamples samples;
    detail::GroupListBuilder::Scratch scratch;
    std::vector<uint32_t> list;
    for (size_t i = range.begin(); i != range.end(); ++i) {
      build_one(in.tree, grid, {uint32_t(pilot(i) / cells), uint32_t(pilot(i) % cells)}, in.trace,
                surfaces ? &*surfaces : nullptr, in.config, samples, scratch, list);
      lengths[i] = list.size();
    }
  });
  double sum = 0.0;
  for (size_t l : lengths) sum += double(l);
  return sum / double(pilots);
}

/// Predicted memory of a grid of about n voxels: the voxel table, the entry tables of the
/// listed voxels and lists of the pilots' mean length (4 bytes an entry, 10 with entry
/// boxes), dedup assumed to save 5 %.
double predicted_bytes(const BuildInputs& in, double n) {
  const ShaftGrid grid(in.box, ShaftGrid::cubical_resolution(in.box, n), in.config.dir_res);
  const Selection sel = detail::select_shafts(grid, in.tris, in.sample_rays, in.config);
  const double mean = mean_pilot_length(in, grid, selected_shafts(grid, sel));
  const size_t listed_voxels = size_t(std::count(sel.voxel_listed.begin(), sel.voxel_listed.end(), 1));
  return 4.0 * double(grid.voxel_count()) + 4.0 * double(listed_voxels) * grid.cells_per_voxel() +
         (in.config.entry_boxes.value() ? 10.0 : 4.0) * 0.95 * mean * double(sel.shafts);
}

/// The voxel count to build for the budget: a secant search in log-log space for the count
/// whose predicted memory is 80-97 % of the budget, at most 8 predictions (two usually settle
/// it; the build's rounds only correct a miss). Memory grows like n (entry tables) when most
/// voxels are listed and like n^(2/3) for surfaces: the first step assumes exponent 1.2, later
/// steps measure it. The grid quantises n, so every step predicts the grid actually built; a
/// step that lands on a grid predicted before goes on to the grid next to the current one
/// instead (else it predicted the same grid up to the last pilot). If none lands in the band,
/// the largest grid predicted within 97 % is kept.
double pilot_voxel_count(const BuildInputs& in, size_t budget) {
  const double cells = 6.0 * in.config.dir_res * in.config.dir_res, max_n = kMaxShafts / cells;
  auto voxels = [&](double m) {
    return double(ShaftGrid(in.box, ShaftGrid::cubical_resolution(in.box, m), 1).voxel_count());
  };
  double n = 4096, prev_n = 0, prev_mem = 0, feasible_n = 1;
  // Grids predicted so far bound the answer: the largest within 97 % and the smallest above.
  double feasible_voxels = 0, over_voxels = kInfinity;
  for (int it = 0; it < 8; ++it) {
    const double real_n = voxels(n);
    const double mem = std::max(1.0, predicted_bytes(in, n));
    const bool over = mem > 0.97 * double(budget);
    if (over) {
      over_voxels = std::min(over_voxels, real_n);
    } else {
      if (mem >= 0.8 * double(budget)) return n;
      if (real_n > feasible_voxels) {
        feasible_voxels = real_n;
        feasible_n = n;
      }
    }
    double slope = 1.2;
    if (prev_n > 0 && std::fabs(std::log(real_n / prev_n)) > 1e-3)
      slope = std::clamp(std::log(mem / prev_mem) / std::log(real_n / prev_n), 0.5, 1.5);
    prev_n = real_n;
    prev_mem = mem;
    const double at = n;
    n = std::clamp(real_n * std::pow(0.9 * double(budget) / mem, 1.0 / slope), real_n / 64.0, real_n * 64.0);
    n = std::clamp(n, 1.0, max_n);
    auto known = [&](double v) { return v == real_n || v <= feasible_voxels || v >= over_voxels; };
    if (known(voxels(n))) {
      // Within one quantisation step of a predicted grid: the next grid down (over the budget)
      // or up (under the band); if that one is known too, no grid lies between the bounds.
      n = at;
      for (int k = 0; k < 1000 && voxels(n) == real_n; ++k) n = std::clamp(n * (over ? 0.98 : 1.02), 1.0, max_n);
      if (known(voxels(n))) return feasible_n;
    }
  }
  return feasible_n;
}

}  // namespace

ShaftCollection ShaftCollection::build(const TreeView& tree, const Bounds3& box, size_t bvh_bytes,
                                       std::span<const Triangle> tris, const TraceFn& trace,
                                       const RayBatch& sample_rays, const ShaftConfig& config_in) {
  const auto t_start = SteadyClock::now();
  const ShaftConfig config = config_in.resolved(tree.arity);
  const size_t budget = config.budget_mib > 0.0 ? size_t(config.budget_mib * 1048576.0)
                                                : size_t(config.budget_rel * double(bvh_bytes));
  double pilot_ms = 0.0;
  auto finish = [&](ShaftCollection col, int rounds) {
    col.stats_.build_rounds = rounds;
    col.stats_.pilot_ms = pilot_ms;
    col.stats_.budget_bytes = budget;
    col.stats_.build_ms = ms_since(t_start);
    return col;
  };
  auto grid_of = [&](double voxels, int dir_res) {
    return ShaftGrid(box, ShaftGrid::cubical_resolution(box, voxels), dir_res);
  };
  if (config.voxels > 0) {
    const ShaftGrid grid = grid_of(double(config.voxels), config.dir_res);
    return finish(build_grid(tree, grid, tris, trace, sample_rays, config), 1);
  }
  double n = pilot_voxel_count({tree, box, tris, trace, sample_rays, config}, budget);
  pilot_ms = ms_since(t_start);
  // Build rounds: the first build is usually within budget; one over it is rebuilt coarser,
  // one far under it (the pilots misjudged) once finer.
  const double cells = 6.0 * config.dir_res * config.dir_res;
  ShaftCollection best;
  bool have_best = false;
  for (int round = 1; round <= 6; ++round) {
    const ShaftGrid grid = grid_of(n, config.dir_res);
    ShaftCollection col = build_grid(tree, grid, tris, trace, sample_rays, config);
    const double mem = double(col.memory_bytes());
    if (mem <= double(budget)) {
      // Far under budget (the pilot misjudged): one finer round at most.
      if (!have_best && mem < 0.4 * double(budget) && round == 1 && grid.voxel_count() > 1) {
        best = std::move(col);
        have_best = true;
        n = std::min(n * std::pow(0.9 * double(budget) / std::max(mem, 1.0), 1.2), kMaxShafts / cells);
        if (grid_of(n, 1).voxel_count() == grid.voxel_count())
          return finish(std::move(best), round);  // already the largest grid
        continue;
      }
      return finish(std::move(col), round);
    }
    if (have_best) return finish(std::move(best), round);
    if (grid.voxel_count() == 1) return finish(std::move(col), round);  // cannot shrink further
    n = std::min(0.8 * double(grid.voxel_count()),
                 double(grid.voxel_count()) * std::pow(0.9 * double(budget) / mem, 1.5));
    n = std::max(1.0, n);
  }
  return finish(build_grid(tree, ShaftGrid(box, {1, 1, 1}, config.dir_res), tris, trace, sample_rays, config), 7);
}

}  // namespace rayscout
