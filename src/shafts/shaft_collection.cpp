// ShaftCollection::build_grid: the lists of one grid, made in parallel voxel by voxel
// (make_lists, VoxelListMaker), then packed (shaft_packing.cpp). The budget search:
// shaft_budget.cpp; selection: shaft_selection.cpp; sample rays: shaft_samples.cpp.
#include "rayscout/shafts/shaft_collection.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <optional>
#include <sstream>

#include <tbb/parallel_for.h>

#include "entry_box_codec.h"
#include "group_list_builder.h"
#include "rayscout/core/machine_memory.h"
#include "rayscout/core/stopwatch.h"
#include "shaft_samples.h"
#include "shaft_selection.h"
#include "voxel_lists.h"

namespace rayscout {

namespace {

using detail::PooledSample;
using detail::Selection;

/// Cells of one cube face rectangle built together (GroupListBuilder), at most 8 x 8: for a
/// Bvh2 (split_by_sign) the members' centre directions also agree on the sign of every
/// component, so that they order children the same way (Algorithm 1 lines 9-14).
struct CellGroup {
  std::vector<uint32_t> cells;
  ShaftGrid::CellRange range;
};

std::vector<CellGroup> cell_groups(const ShaftGrid& grid, bool split_by_sign) {
  const int d = grid.dir_res();
  std::vector<CellGroup> groups;
  for (int face = 0; face < 6; ++face) {
    const ShaftGrid::CellRange f = grid.cell_range(uint32_t(face * d * d));
    const auto [ua, va] = ShaftGrid::face_axes(f.axis);
    // Runs of cells along u (and v) whose centre component has the same sign, cut to <= 8.
    auto runs = [&](int comp, bool along_u) {
      std::vector<std::pair<int, int>> out;
      int begin = 0;
      auto positive = [&](int i) {
        const uint32_t cell = uint32_t((face * d + (along_u ? 0 : i)) * d + (along_u ? i : 0));
        return Shaft(grid, {0, cell}).center_dir()[comp] > 0.0f;
      };
      for (int i = 1; i <= d; ++i)
        if (i == d || (split_by_sign && positive(i) != positive(begin)) || i - begin == 8) {
          out.push_back({begin, i});
          begin = i;
        }
      return out;
    };
    for (const auto& [v0, v1] : runs(va, false))
      for (const auto& [u0, u1] : runs(ua, true)) {
        CellGroup g;
        for (int v = v0; v < v1; ++v)
          for (int u = u0; u < u1; ++u) g.cells.push_back(uint32_t((face * d + v) * d + u));
        const auto lo = grid.cell_range(g.cells.front()), hi = grid.cell_range(g.cells.back());
        g.range = {lo.axis, lo.sign, lo.u0, hi.u1, lo.v0, hi.v1};
        groups.push_back(std::move(g));
      }
  }
  return groups;
}

/// The cones of a grid's shafts, the same in every voxel: made once at voxel 0, moved to each
/// voxel (Shaft::set_voxel) or used for their axes alone.
struct GridCones {
  std::vector<Shaft> cell;         ///< one per direction cell
  std::vector<CellGroup> groups;   ///< the cells built together
  std::vector<Shaft> group;        ///< one per group: the union of its cells
  GridCones(const ShaftGrid& grid, bool split_by_sign) : groups(cell_groups(grid, split_by_sign)) {
    for (uint32_t c = 0; c < grid.cells_per_voxel(); ++c) cell.emplace_back(grid, ShaftCoord{0, c});
    for (const CellGroup& g : groups) group.emplace_back(grid, 0, g.range);
  }
};

/// The sample rays of one listed voxel in a cell-major pool: cell c's config.samples rays
/// start at first + c * stride.
struct VoxelSamples {
  const PooledSample* first;
  size_t stride;
  const PooledSample* of_cell(uint32_t cell) const { return first + size_t(cell) * stride; }
};

/// Algorithm 1 for every selected shaft of one listed voxel, a cell group at a time
/// (GroupListBuilder), with the overflow policy (retry_overflow) and the cullNodeSubtree(root)
/// fallback. One per task: it owns the task's scratch.
class VoxelListMaker {
 public:
  struct Context {
    const TreeView& tree;  ///< not empty
    const ShaftGrid& grid;
    const ShaftConfig& config;  ///< resolved (min_prob filled in)
    const GridCones& cones;
    const std::vector<uint8_t>& shaft_selected;  ///< Selection::shaft_selected
  };
  explicit VoxelListMaker(const Context& c) : c_(c), lists_(detail::GroupListBuilder::kMaxGroup) {}

  /// The lists of `voxel` into vl.
  void make(uint32_t voxel, const VoxelSamples& samples, detail::VoxelLists& vl) {
    const uint32_t cells = c_.grid.cells_per_voxel();
    vl.status.assign(cells, detail::VoxelLists::kNoList);
    vl.len.assign(cells, 0);
    vl.begin.assign(cells, 0);
    for (size_t gi = 0; gi < c_.cones.groups.size(); ++gi) {
      select_members(voxel, c_.cones.groups[gi]);
      if (members_.empty()) continue;
      gather_samples(samples);
      Shaft group = c_.cones.group[gi];
      group.set_voxel(c_.grid, voxel);
      build_member_lists(group, vl);
      store_member_lists(vl);
    }
  }

 private:
  /// The group's selected cells: members_ (their cones) and member_cells_.
  void select_members(uint32_t voxel, const CellGroup& g) {
    const uint64_t first_shaft = uint64_t(voxel) * c_.grid.cells_per_voxel();
    members_.clear();
    member_cells_.clear();
    for (uint32_t cell : g.cells) {
      if (!c_.shaft_selected.empty() && !c_.shaft_selected[first_shaft + cell]) continue;
      members_.push_back(&c_.cones.cell[cell]);  // cones only (GroupListBuilder)
      member_cells_.push_back(cell);
    }
  }

  /// The members' sample rays, member after member, into samples_ (GroupListBuilder's layout).
  void gather_samples(const VoxelSamples& samples) {
    const size_t per = size_t(c_.config.samples.value());
    samples_.resize(members_.size() * per);
    for (size_t m = 0; m < members_.size(); ++m) {
      const PooledSample* from = samples.of_cell(member_cells_[m]);
      for (size_t k = 0; k < per; ++k) {
        const size_t i = m * per + k;
        samples_.ox[i] = from[k].org[0]; samples_.oy[i] = from[k].org[1]; samples_.oz[i] = from[k].org[2];
        samples_.ix[i] = from[k].inv_dir[0]; samples_.iy[i] = from[k].inv_dir[1]; samples_.iz[i] = from[k].inv_dir[2];
        samples_.hit_t[i] = from[k].hit_t;
      }
    }
  }

  /// Algorithm 1 for every member into lists_; the members whose list overflows are rebuilt
  /// together by retry_overflow, and those still too long get cullNodeSubtree(root).
  void build_member_lists(const Shaft& group, detail::VoxelLists& vl) {
    const ShaftConfig& config = c_.config;
    detail::GroupListBuilder builder(c_.tree, group, members_, samples_, config.samples.value(), scratch_);
    const uint64_t all = members_.size() == 64 ? ~uint64_t(0) : (uint64_t(1) << members_.size()) - 1;
    uint64_t failed = all & ~builder.build(config.min_prob, config.max_list, all, lists_.data());
    if (failed)
      detail::retry_overflow(
          config.near_retries, config.retries, config.min_prob, config.samples.value(), length(group.voxel().diagonal()),
          [&](double p, bool clamped) {
            (clamped ? vl.near_retries : vl.retries) += size_t(std::popcount(failed));
            failed &= ~builder.build(p, config.max_list, failed, lists_.data());
            return failed == 0;
          },
          [&](float reach) { samples_.clamp_hits(reach); });
    vl.fallbacks += size_t(std::popcount(failed));
    builder.fallback(failed, lists_.data());
  }

  /// The members' lists into vl: an empty list marks a shaft that reaches no geometry.
  void store_member_lists(detail::VoxelLists& vl) const {
    for (size_t m = 0; m < members_.size(); ++m) {
      const std::vector<uint32_t>& list = lists_[m];
      const uint32_t cell = member_cells_[m];
      if (list.empty()) {
        vl.status[cell] = detail::VoxelLists::kReachesNothing;
        continue;
      }
      vl.status[cell] = detail::VoxelLists::kList;
      vl.len[cell] = uint8_t(list.size());
      vl.begin[cell] = uint32_t(vl.data.size());
      vl.data.insert(vl.data.end(), list.begin(), list.end());
    }
  }

  const Context& c_;
  detail::ShaftSamples samples_;
  std::vector<const Shaft*> members_;
  std::vector<uint32_t> member_cells_;
  std::vector<std::vector<uint32_t>> lists_;
  detail::GroupListBuilder::Scratch scratch_;
};

}  // namespace

std::string ShaftStats::summary() const {
  std::ostringstream s;
  s << "grid " << res[0] << "x" << res[1] << "x" << res[2] << " voxels, d=" << dir_res << " ("
    << 6 * dir_res * dir_res << " cells/voxel); listed voxels " << listed_voxels << "/" << voxels
    << ", listed shafts " << listed_shafts << "/" << shafts << " (" << empty_lists << " reach nothing)\n"
    << "memory: lookup " << lookup_bytes / 1024.0 << " KiB + lists " << list_bytes / 1024.0
    << " KiB = " << memory_bytes() / 1048576.0 << " MiB (budget " << budget_bytes / 1048576.0
    << " MiB); dedup saved " << dedup_saved_bytes / 1024.0 << " KiB, " << unique_lists << " unique lists\n"
    << "lists: mean length " << mean_list << ", max " << max_list << "; overflow: " << near_retries
    << " rebuilds with clamped distances, " << overflow_retries << " with raised thresholds, " << overflow_fallbacks
    << " fallbacks\n"
    << "build " << build_ms << " ms in " << build_rounds << " round(s) (budget pilots " << pilot_ms
    << " ms); last round: selection " << select_ms
    << " ms, lists " << lists_ms << " ms (sample-ray tracing " << samples_ms << " CPU ms over all threads), packing " << pack_ms << " ms";
  if (traced_samples > 0) s << "; " << traced_samples << " shared sample rays traced";
  return s.str();
}

namespace {

/// "RXxRYxRZ voxels x N direction cells", for messages.
std::string grid_name(const ShaftGrid& grid) {
  return std::to_string(grid.res()[0]) + "x" + std::to_string(grid.res()[1]) + "x" + std::to_string(grid.res()[2]) +
         " voxels x " + std::to_string(grid.cells_per_voxel()) + " direction cells";
}

/// A grid of 2^32 shafts or more cannot be addressed (ShaftCoord, the entry table).
void require_addressable(const ShaftGrid& grid) {
  const size_t shafts = grid.voxel_count() * grid.cells_per_voxel();
  if (shafts >= (size_t(1) << 32) - 64)
    throw InputError("shafts: a grid of " + grid_name(grid) + " is " + std::to_string(shafts) +
                     " shafts, more than 2^32; lower voxels or dir_res");
}

/// Refuses a grid the machine cannot build. What the build holds at once, a lower bound (the
/// lists themselves are not counted): the shared sample rays, each voxel's lists before
/// packing, the entry and dedup tables, the voxel tables. It can be 10-30x the collection
/// (Cornell box, shafts-wide, budget_mib=512: 8.1 GB estimated, 10.1 GB measured, for 0.41 GB).
void require_build_memory(const ShaftGrid& grid, size_t listed_voxels, const ShaftConfig& config) {
  const double listed_shafts = double(listed_voxels) * grid.cells_per_voxel();
  const double shared_bytes =
      config.reuse_rays.value() ? double(config.samples.value() * sizeof(PooledSample) + 2) : 0.0;
  require_memory(listed_shafts * (shared_bytes + 30.0) + double(listed_voxels) * sizeof(detail::VoxelLists) +
                     5.0 * double(grid.voxel_count()),
                 "shafts: building a grid of " + grid_name(grid) + " (" + std::to_string(listed_voxels) +
                     " voxels listed; budget_mib, budget_rel or voxels decide the grid) needs");
}

/// Without a tree there is no geometry: every selected shaft reaches nothing.
void mark_unreachable(const ShaftGrid& grid, const std::vector<uint32_t>& listed, const Selection& sel,
                      std::vector<detail::VoxelLists>& lists) {
  const uint32_t cells = grid.cells_per_voxel();
  for (size_t li = 0; li < listed.size(); ++li) {
    detail::VoxelLists& vl = lists[li];
    vl.status.assign(cells, detail::VoxelLists::kNoList);
    vl.len.assign(cells, 0);
    vl.begin.assign(cells, 0);
    for (uint32_t cell = 0; cell < cells; ++cell)
      if (sel.shaft_selected.empty() || sel.shaft_selected[uint64_t(listed[li]) * cells + cell])
        vl.status[cell] = detail::VoxelLists::kReachesNothing;
  }
}

/// What make_lists reports of the sample rays: the time spent tracing them (summed over the
/// tasks when traced per chunk) and, when shared along their paths, how many were traced.
struct SampleFigures {
  double ms = 0.0;
  size_t traced = 0;
};

/// Algorithm 1 for every selected shaft of the listed voxels (tree not empty), in parallel:
/// the lists of listed[li] into lists[li]. Their sample rays are traced first for all voxels
/// (shared along their paths, reuse_rays) or per chunk of kChunk voxels just before their walks.
SampleFigures make_lists(const TreeView& tree, const ShaftGrid& grid, std::span<const Triangle> tris,
                         const ShaftCollection::TraceFn& trace, const ShaftConfig& config, const Selection& sel,
                         const std::vector<uint32_t>& listed, std::vector<detail::VoxelLists>& lists) {
  SampleFigures figures;
  const uint32_t cells = grid.cells_per_voxel();
  const size_t per = size_t(config.samples.value());
  // Bvh2 lists keep their per-shaft order only when the members agree on the child order
  // (centre-direction signs); k-ary trees are ordered by the group direction anyway.
  const GridCones cones(grid, tree.split_order);
  std::optional<detail::VoxelSurfaces> surfaces;
  if (config.origins == SampleOrigins::Surface) surfaces.emplace(grid, tris, listed);
  const detail::VoxelSurfaces* origins = surfaces ? &*surfaces : nullptr;

  std::vector<PooledSample> shared;
  const auto t_samples = SteadyClock::now();
  if (config.reuse_rays.value()) {
    std::vector<int32_t> listed_index(grid.voxel_count(), -1);
    for (size_t li = 0; li < listed.size(); ++li) listed_index[listed[li]] = int32_t(li);
    shared.resize(listed.size() * cells * per);
    std::vector<uint16_t> count(listed.size() * cells, 0);  // samples <= 1000
    figures.traced =
        detail::shared_samples(grid, listed, listed_index, sel.shaft_selected, origins, trace, config, shared, count);
    figures.ms = ms_since(t_samples);
  }
  const bool chunked = !config.reuse_rays.value();
  std::atomic<int64_t> chunk_trace_ns{0};
  constexpr size_t kChunk = 32;
  const VoxelListMaker::Context context{tree, grid, config, cones, sel.shaft_selected};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, listed.size(), kChunk / 2), [&](const auto& range) {
    VoxelListMaker maker(context);
    std::vector<PooledSample> chunk;
    size_t chunk_begin = 0, chunk_end = 0;
    for (size_t li = range.begin(); li != range.end(); ++li) {
      if (chunked && li >= chunk_end) {
        const auto t0 = SteadyClock::now();
        chunk_begin = li;
        chunk_end = std::min(range.end(), li + kChunk);
        detail::cell_major_samples(grid, listed, chunk_begin, chunk_end, sel.shaft_selected, origins, trace, config,
                                   chunk);
        chunk_trace_ns += std::chrono::duration_cast<std::chrono::nanoseconds>(SteadyClock::now() - t0).count();
      }
      // Both pools are cell-major: [cell][listed voxel][sample].
      const VoxelSamples samples =
          chunked ? VoxelSamples{chunk.data() + (li - chunk_begin) * per, (chunk_end - chunk_begin) * per}
                  : VoxelSamples{shared.data() + li * per, listed.size() * per};
      maker.make(listed[li], samples, lists[li]);
    }
  });
  if (chunked) figures.ms = double(chunk_trace_ns.load()) * 1e-6;
  return figures;
}

}  // namespace

ShaftCollection ShaftCollection::build_grid(const TreeView& tree, const ShaftGrid& grid,
                                            std::span<const Triangle> tris, const TraceFn& trace,
                                            const RayBatch& sample_rays, const ShaftConfig& config_in) {
  const auto t_start = SteadyClock::now();
  const ShaftConfig config = config_in.resolved(tree.arity);
  ShaftCollection col;
  col.grid_ = grid;
  if (config.entry_boxes.value()) col.entry_codec_ = std::make_shared<const detail::EntryBoxCodec>(grid.box());
  require_addressable(grid);
  const Selection sel = detail::select_shafts(grid, tris, sample_rays, config);
  std::vector<uint32_t> listed;
  for (uint32_t v = 0; v < grid.voxel_count(); ++v)
    if (sel.voxel_listed[v]) listed.push_back(v);
  const double select_ms = ms_since(t_start);

  const auto t_lists = SteadyClock::now();
  require_build_memory(grid, listed.size(), config);
  std::vector<detail::VoxelLists> lists(listed.size());  // per listed voxel, its lists before packing
  if (tree.size() == 0) {
    mark_unreachable(grid, listed, sel, lists);
  } else {
    const SampleFigures samples = make_lists(tree, grid, tris, trace, config, sel, listed, lists);
    col.stats_.samples_ms = samples.ms;
    col.stats_.traced_samples = samples.traced;
  }
  const double lists_ms = ms_since(t_lists);

  const auto t_pack = SteadyClock::now();
  col.pack(tree, listed, lists, config.dedup);
  ShaftStats& st = col.stats_;
  st.select_ms = select_ms;
  st.lists_ms = lists_ms;
  st.pack_ms = ms_since(t_pack);
  st.build_rounds = 1;
  st.build_ms = ms_since(t_start);
  return col;
}

}  // namespace rayscout
