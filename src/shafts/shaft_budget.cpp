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
                            surfaces, coord.voxel, trace, config, [&](size_t s, const Ray& ray, float hit_t) { detail::store_sample(samples, s, ray.org, ray.dir, hit_t); });
  const Shaft* const member = &shaft;
  detail::GroupListBuilder builder(tree, shaft, {&member, 1}, samples, config.samples.value(), scratch);
  auto fits = [&](double min_prob) { return builder.build(min_prob, config.max_list, 1, &list) == 1; };
  const bool ok = fits(config.min_prob) ||
                  detail::retry_overflow(
                      config.near_retries, config.retries, config.min_prob, length(shaft.voxel().diagonal()),
                      [&](double p, bool) { return fits(p); }, [&](float reach) { samples.clamp_hits(reach); });
  if (!ok) builder.fallback(1, &list);
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
  if (config.voxels > 0) {
    const ShaftGrid grid(box, ShaftGrid::cubical_resolution(box, double(config.voxels)), config.dir_res);
    return finish(build_grid(tree, grid, tris, trace, sample_rays, config), 1);
  }
  const double cells = 6.0 * config.dir_res * config.dir_res;
  // Predicted memory of a grid of about n voxels: the voxel table, entry tables of the listed
  // voxels and lists whose mean length a pilot of up to 192 random listed shafts measures
  // (dedup assumed to save 5 %). Two pilot iterations settle the resolution before the one
  // real build; the loop below only corrects a miss.
  auto predict = [&](double n) {
    const ShaftGrid grid(box, ShaftGrid::cubical_resolution(box, n), config.dir_res);
    const Selection sel = detail::select_shafts(grid, tris, sample_rays, config);
    std::vector<uint64_t> ids;
    for (uint32_t v = 0; v < grid.voxel_count(); ++v) {
      if (!sel.voxel_listed[v]) continue;
      for (uint32_t c = 0; c < grid.cells_per_voxel(); ++c) {
        const uint64_t id = uint64_t(v) * grid.cells_per_voxel() + c;
        if (sel.shaft_selected.empty() || sel.shaft_selected[id]) ids.push_back(id);
      }
    }
    const size_t pilots = std::min<size_t>(192, ids.size());
    std::optional<detail::VoxelSurfaces> surfaces;
    if (config.origins == SampleOrigins::Surface && tree.size() > 0) {
      std::vector<uint32_t> voxels;
      for (size_t i = 0; i < pilots; ++i) voxels.push_back(uint32_t(ids[i * ids.size() / pilots] / grid.cells_per_voxel()));
      voxels.erase(std::unique(voxels.begin(), voxels.end()), voxels.end());
      surfaces.emplace(grid, tris, voxels);
    }
    std::vector<size_t> lengths(pilots, 0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, pilots, 8), [&](const auto& range) {
      detail::ShaftSamples samples;
      detail::GroupListBuilder::Scratch scratch;
      std::vector<uint32_t> list;
      for (size_t i = range.begin(); i != range.end(); ++i) {
        const uint64_t id = ids[i * ids.size() / pilots];
        build_one(tree, grid, {uint32_t(id / grid.cells_per_voxel()), uint32_t(id % grid.cells_per_voxel())},
                  trace, surfaces ? &*surfaces : nullptr, config, samples, scratch, list);
        lengths[i] = list.size();
      }
    });
    double mean = 0.0;
    for (size_t l : lengths) mean += double(l);
    mean = pilots ? mean / double(pilots) : 0.0;
    const size_t listed_voxels = size_t(std::count(sel.voxel_listed.begin(), sel.voxel_listed.end(), 1));
    return 4.0 * double(grid.voxel_count()) + 4.0 * double(listed_voxels) * cells +
           (config.entry_boxes.value() ? 10.0 : 4.0) * 0.95 * mean * double(sel.shafts);
  };
  // Secant search in log-log space for the voxel count whose predicted memory is 80-97 % of
  // the budget. Memory grows like n (entry tables) when most voxels are listed and like n^(2/3)
  // for surfaces: the first step assumes exponent 1.2, later steps measure it. The grid
  // quantises n, so every step predicts the grid actually built; the largest grid predicted
  // within budget is kept.
  double n = 4096, prev_n = 0, prev_mem = 0, feasible_n = 1;
  bool settled = false;
  for (int it = 0; it < 8 && !settled; ++it) {
    const double real_n = double(ShaftGrid(box, ShaftGrid::cubical_resolution(box, n), 1).voxel_count());
    const double mem = std::max(1.0, predict(n));
    if (mem <= 0.97 * double(budget)) {
      feasible_n = std::max(feasible_n, n);
      settled = mem >= 0.8 * double(budget);
      if (settled) break;
    }
    double slope = 1.2;
    if (prev_n > 0 && std::fabs(std::log(real_n / prev_n)) > 1e-3)
      slope = std::clamp(std::log(mem / prev_mem) / std::log(real_n / prev_n), 0.5, 1.5);
    prev_n = real_n;
    prev_mem = mem;
    n = std::clamp(real_n * std::pow(0.9 * double(budget) / mem, 1.0 / slope), real_n / 64.0, real_n * 64.0);
    n = std::clamp(n, 1.0, kMaxShafts / cells);
  }
  if (!settled) n = feasible_n;
  pilot_ms = ms_since(t_start);
  ShaftCollection best;
  bool have_best = false;
  for (int round = 1; round <= 6; ++round) {
    const ShaftGrid grid(box, ShaftGrid::cubical_resolution(box, n), config.dir_res);
    ShaftCollection col = build_grid(tree, grid, tris, trace, sample_rays, config);
    const double mem = double(col.memory_bytes());
    if (mem <= double(budget)) {
      // Far under budget (the pilot misjudged): one finer round at most.
      if (!have_best && mem < 0.4 * double(budget) && round == 1 && grid.voxel_count() > 1) {
        best = std::move(col);
        have_best = true;
        n = std::min(n * std::pow(0.9 * double(budget) / std::max(mem, 1.0), 1.2), kMaxShafts / cells);
        if (ShaftGrid(box, ShaftGrid::cubical_resolution(box, n), 1).voxel_count() == grid.voxel_count())
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
  const ShaftGrid grid(box, {1, 1, 1}, config.dir_res);
  return finish(build_grid(tree, grid, tris, trace, sample_rays, config), 7);
}

}  // namespace rayscout
