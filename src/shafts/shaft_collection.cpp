// ShaftCollection: parallel list construction of one grid (build_grid) and deduplication and
// packing (pack). The budget search: shaft_budget.cpp; selection: shaft_selection.cpp;
// sample rays: shaft_samples.cpp.
#include "rayscout/shafts/shaft_collection.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "entry_box_codec.h"
#include "group_list_builder.h"
#include "rayscout/core/machine_memory.h"
#include "rayscout/core/stopwatch.h"
#include "shaft_samples.h"
#include "shaft_selection.h"

namespace rayscout {

namespace detail {
/// The lists of one listed voxel before packing: per cell a status and the cell's list,
/// concatenated in data.
struct VoxelLists {
  enum Status : uint8_t { kNoList, kList, kReachesNothing };
  std::vector<Status> status;
  std::vector<uint8_t> len;
  std::vector<uint32_t> begin;  ///< start of the cell's list in data (groups fill data out of cell order)
  std::vector<uint32_t> data;
  size_t near_retries = 0, retries = 0, fallbacks = 0;
};
}  // namespace detail

namespace {

using detail::PooledSample;
using detail::Selection;

/// Cells of one cube face rectangle built together (GroupListBuilder): the members' centre
/// directions agree on the sign of every component, at most 8 x 8 cells.
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

/// Algorithm 1 for every selected shaft of one listed voxel, a cell group at a time
/// (GroupListBuilder), with the raised thresholds on overflow and the cullNodeSubtree(root)
/// fallback. One per task: it owns the task's scratch.
class VoxelListMaker {
 public:
  struct Context {
    const TreeView& tree;
    const ShaftGrid& grid;
    const ShaftConfig& config;  ///< resolved (min_prob filled in)
    const std::vector<CellGroup>& groups;
    const std::vector<Shaft>& group_shafts;  ///< one group cone per group, at voxel 0
    const std::vector<Shaft>& cell_shafts;   ///< one cone per cell, at voxel 0
    const std::vector<uint8_t>& shaft_selected;
  };
  explicit VoxelListMaker(const Context& c) : c_(c), lists_(detail::GroupListBuilder::kMaxGroup) {}

  /// The lists of voxel into vl; samples_of(cell) points at the cell's config.samples
  /// sample rays of this voxel.
  template <class SamplesOf>
  void make(uint32_t voxel, SamplesOf&& samples_of, detail::VoxelLists& vl) {
    const TreeView& tree = c_.tree;
    const uint32_t cells = c_.grid.cells_per_voxel();
    const size_t per = size_t(c_.config.samples.value());
    vl.status.assign(cells, detail::VoxelLists::kNoList);
    vl.len.assign(cells, 0);
    vl.begin.assign(cells, 0);
    for (size_t gi = 0; gi < c_.groups.size(); ++gi) {
      members_.clear();
      member_cells_.clear();
      for (uint32_t cell : c_.groups[gi].cells) {
        if (!c_.shaft_selected.empty() && !c_.shaft_selected[uint64_t(voxel) * cells + cell]) continue;
        members_.push_back(&c_.cell_shafts[cell]);  // cones only (GroupListBuilder)
        member_cells_.push_back(cell);
      }
      if (members_.empty()) continue;
      Shaft group = c_.group_shafts[gi];
      group.set_voxel(c_.grid, voxel);
      samples_.resize(members_.size() * per);
      // Without a tree there is nothing to walk, and no samples were traced.
      for (size_t m = 0; m < members_.size() && tree.size() > 0; ++m) {
        const PooledSample* from = samples_of(member_cells_[m]);
        for (size_t k = 0; k < per; ++k) {
          const size_t i = m * per + k;
          samples_.ox[i] = from[k].org[0]; samples_.oy[i] = from[k].org[1]; samples_.oz[i] = from[k].org[2];
          samples_.ix[i] = from[k].inv_dir[0]; samples_.iy[i] = from[k].inv_dir[1]; samples_.iz[i] = from[k].inv_dir[2];
          samples_.hit_t[i] = from[k].hit_t;
        }
      }
      const uint64_t all = members_.size() == 64 ? ~uint64_t(0) : (uint64_t(1) << members_.size()) - 1;
      if (tree.size() > 0) {
        detail::GroupListBuilder builder(tree, group, members_, samples_, int(per), scratch_);
        uint64_t failed = all & ~builder.build(c_.config.min_prob, c_.config.max_list, all, lists_.data());
        // Overflowing members retry together (retry_overflow: clamped distances, then raised
        // thresholds), then fall back to cullNodeSubtree(root).
        if (failed)
          detail::retry_overflow(
              c_.config.near_retries, c_.config.retries, c_.config.min_prob, length(group.voxel().diagonal()),
              [&](double p, bool clamped) {
                (clamped ? vl.near_retries : vl.retries) += size_t(std::popcount(failed));
                failed &= ~builder.build(p, c_.config.max_list, failed, lists_.data());
                return failed == 0;
              },
              [&](float reach) { samples_.clamp_hits(reach); });
        vl.fallbacks += size_t(std::popcount(failed));
        builder.fallback(failed, lists_.data());
      }
      for (size_t m = 0; m < members_.size(); ++m) {
        std::vector<uint32_t>& list = lists_[m];
        if (tree.size() == 0) list.clear();
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
  }

 private:
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

// Identical lists are stored once: open addressing over the lists' contents, sized for every
// listed shaft at load <= 1/2. A slot holds a list's hash and its packed entry (offset << 5 |
// length) plus 1, 0 = free, side by side: one cache miss per probe (the table is ~8 MiB).
class ListDedup {
 public:
  explicit ListDedup(size_t lists) {
    size_t capacity = 1024;
    while (capacity < 2 * lists) capacity *= 2;
    slots_.resize(capacity);
    mask_ = capacity - 1;
  }
  void prefetch(uint32_t hash) const { __builtin_prefetch(&slots_[hash & mask_]); }
  // The offset of an earlier list equal to area[offset, offset + len); else remembers this
  // one and returns nothing.
  std::optional<uint32_t> find_or_add(uint32_t hash, const std::vector<uint32_t>& area, uint32_t offset, uint32_t len) {
    size_t slot = hash & mask_;
    for (; slots_[slot].list != 0; slot = (slot + 1) & mask_) {
      if (slots_[slot].hash != hash) continue;
      const uint32_t packed = slots_[slot].list - 1, o = packed >> 5;
      if ((packed & 31u) == len && std::equal(area.begin() + o, area.begin() + o + len, area.begin() + offset))
        return o;
    }
    slots_[slot] = {hash, ((offset << 5) | len) + 1};
    return std::nullopt;
  }

 private:
  struct Slot {
    uint32_t hash = 0, list = 0;
  };
  std::vector<Slot> slots_;
  size_t mask_ = 0;
};

// FNV-1a over a list's node references.
uint32_t hash_list(const TreeView& tree, const uint32_t* nodes, uint32_t len) {
  uint64_t h = 1469598103934665603ull ^ len;
  for (uint32_t i = 0; i < len; ++i) h = (h ^ tree.ref[nodes[i]]) * 1099511628211ull;
  return uint32_t(h ^ (h >> 32));
}

}  // namespace

void ShaftCollection::pack(const TreeView& tree, const std::vector<uint32_t>& listed,
                           const std::vector<detail::VoxelLists>& out, bool dedup) {
  const uint32_t cells = grid_.cells_per_voxel();
  const size_t nvox = grid_.voxel_count();
  ShaftStats& st = stats_;
  st.res = grid_.res();
  st.dir_res = grid_.dir_res();
  st.voxels = nvox;
  st.shafts = nvox * cells;
  st.listed_voxels = listed.size();
  st.length_histogram.assign(32, 0);
  voxel_base_.assign(nvox, kNoVoxel);
  entries_.assign(listed.size() * cells, 0);
  ListDedup table(dedup ? listed.size() * cells : 0);
  // Hashes of every list in packing order first, so that the probe of the list kAhead lists
  // later can be prefetched (the probes are random accesses into a table of several MiB).
  std::vector<uint32_t> hashes;
  size_t total_entries = 0;
  for (const detail::VoxelLists& vl : out) {
    total_entries += vl.data.size();
    if (!dedup) continue;
    for (uint32_t cell = 0; cell < cells; ++cell)
      if (vl.status[cell] == detail::VoxelLists::kList)
        hashes.push_back(hash_list(tree, vl.data.data() + vl.begin[cell], vl.len[cell]));
  }
  constexpr size_t kAhead = 8;
  size_t next_hash = 0;
  // Entry boxes are quantised once per tree node.
  std::vector<detail::QBox> qboxes(boxed() ? tree.size() : 0);
  std::vector<uint8_t> quantised(qboxes.size(), 0);
  lists_.reserve(total_entries * (boxed() ? 3 : 1) + 2);
  size_t total_len = 0, nonempty = 0, unique = 0;
  for (size_t li = 0; li < listed.size(); ++li) {
    const detail::VoxelLists& vl = out[li];
    const uint32_t base = uint32_t(li * cells);
    voxel_base_[listed[li]] = base;
    st.near_retries += vl.near_retries;
    st.overflow_retries += vl.retries;
    st.overflow_fallbacks += vl.fallbacks;
    for (uint32_t cell = 0; cell < cells; ++cell) {
      if (vl.status[cell] == detail::VoxelLists::kNoList) continue;
      ++st.listed_shafts;
      if (vl.status[cell] == detail::VoxelLists::kReachesNothing) {
        ++st.empty_lists;
        entries_[base + cell] = kEmptyList;
        continue;
      }
      const uint32_t len = vl.len[cell];
      const uint32_t* nodes = vl.data.data() + vl.begin[cell];
      // Append the list, then take it back if an equal one is stored already.
      const uint32_t offset = uint32_t(lists_.size());
      for (uint32_t k = 0; k < len; ++k) lists_.push_back(tree.ref[nodes[k]]);
      std::optional<uint32_t> twin;
      if (dedup) {
        if (next_hash + kAhead < hashes.size()) table.prefetch(hashes[next_hash + kAhead]);
        twin = table.find_or_add(hashes[next_hash++], lists_, offset, len);
      }
      if (twin) {
        lists_.resize(offset);
        st.dedup_saved_bytes += list_words(len) * sizeof(uint32_t);
      } else {
        if (offset >= (1u << 27)) throw InputError("shafts: list area exceeds 2^27 entries; lower the resolution");
        ++unique;
        if (boxed()) {
          // The rows follow the list's ids in the same area: one cache line serves both.
          uint8_t rows[6 * 31];
          for (uint32_t k = 0; k < len; ++k) {
            const uint32_t node = nodes[k];
            if (!quantised[node]) {
              qboxes[node] = entry_codec_->encode(tree.bounds[node]);
              quantised[node] = 1;
            }
            for (int row = 0; row < 3; ++row) {
              rows[size_t(row) * len + k] = qboxes[node].lo[row];
              rows[size_t(row + 3) * len + k] = qboxes[node].hi[row];
            }
          }
          const size_t at_rows = lists_.size();
          lists_.resize(offset + list_words(len), 0);
          std::memcpy(lists_.data() + at_rows, rows, 6 * size_t(len));
        }
      }
      entries_[base + cell] = (twin.value_or(offset) << 5) | len;
      ++st.length_histogram[len];
      total_len += len;
      ++nonempty;
      st.max_list = std::max(st.max_list, int(len));
    }
  }
  if (boxed()) lists_.resize(lists_.size() + 2, 0);  // SIMD rows read 8 bytes
  lists_.shrink_to_fit();
  st.unique_lists = unique;
  st.mean_list = nonempty ? double(total_len) / double(nonempty) : 0.0;
  st.lookup_bytes = (voxel_base_.size() + entries_.size()) * sizeof(uint32_t);
  st.list_bytes = lists_.size() * sizeof(uint32_t);  // ids (and entry-box rows)
}

ShaftCollection ShaftCollection::build_grid(const TreeView& tree, const ShaftGrid& grid,
                                            std::span<const Triangle> tris, const TraceFn& trace,
                                            const RayBatch& sample_rays, const ShaftConfig& config_in) {
  const auto t_start = SteadyClock::now();
  const ShaftConfig config = config_in.resolved(tree.arity);
  ShaftCollection col;
  col.grid_ = grid;
  if (config.entry_boxes.value()) col.entry_codec_ = std::make_shared<const detail::EntryBoxCodec>(grid.box());
  const uint32_t cells = grid.cells_per_voxel();
  const size_t nvox = grid.voxel_count();
  const std::string grid_name = std::to_string(grid.res()[0]) + "x" + std::to_string(grid.res()[1]) + "x" +
                                std::to_string(grid.res()[2]) + " voxels x " + std::to_string(cells) + " direction cells";
  if (nvox * cells >= (size_t(1) << 32) - 64)
    throw InputError("shafts: a grid of " + grid_name + " is " + std::to_string(nvox * cells) +
                     " shafts, more than 2^32; lower voxels or dir_res");

  Selection sel = detail::select_shafts(grid, tris, sample_rays, config);
  const double select_ms = ms_since(t_start);
  const auto t_lists = SteadyClock::now();
  std::vector<uint8_t>& voxel_listed = sel.voxel_listed;
  std::vector<uint8_t>& shaft_selected = sel.shaft_selected;
  std::vector<uint32_t> listed;
  for (uint32_t v = 0; v < nvox; ++v)
    if (voxel_listed[v]) listed.push_back(v);
  const size_t per = size_t(config.samples.value());
  // What the build holds at once, a lower bound (the lists themselves are not counted): the
  // shared sample rays, each voxel's lists before packing, the entry and dedup tables, the
  // voxel tables. It can be 10-30x the collection (Cornell box, shafts-wide, budget_mib=512:
  // 8.1 GB estimated, 10.1 GB measured, for 0.41 GB), so a grid the machine cannot build is
  // refused up front.
  const double listed_shafts = double(listed.size()) * cells;
  require_memory(listed_shafts * ((config.reuse_rays.value() ? double(per * sizeof(PooledSample) + 2) : 0.0) + 30.0) +
                     double(listed.size()) * sizeof(detail::VoxelLists) + 5.0 * double(nvox),
                 "shafts: building a grid of " + grid_name + " (" + std::to_string(listed.size()) +
                     " voxels listed; budget_mib, budget_rel or voxels decide the grid) needs");

  std::vector<detail::VoxelLists> out(listed.size());  // per listed voxel, its lists before packing

  // Cones are the same in every voxel: made once, moved to each voxel.
  std::vector<Shaft> cell_shafts;
  for (uint32_t cell = 0; cell < cells; ++cell) cell_shafts.emplace_back(grid, ShaftCoord{0, cell});
  // Bvh2 lists keep their per-shaft order only when the members agree on the child order
  // (centre-direction signs); k-ary trees are ordered by the group direction anyway.
  const std::vector<CellGroup> groups = cell_groups(grid, tree.split_order);
  std::vector<Shaft> group_shafts;
  for (const CellGroup& g : groups) group_shafts.emplace_back(grid, 0, g.range);
  const std::optional<detail::VoxelSurfaces> surfaces =
      config.origins == SampleOrigins::Surface && tree.size() > 0
          ? std::optional<detail::VoxelSurfaces>(std::in_place, grid, tris, listed)
          : std::nullopt;
  const detail::VoxelSurfaces* origins = surfaces ? &*surfaces : nullptr;
  std::vector<PooledSample> pool;
  const auto t_samples = SteadyClock::now();
  if (config.reuse_rays.value() && tree.size() > 0) {
    std::vector<int32_t> listed_index(nvox, -1);
    for (size_t li = 0; li < listed.size(); ++li) listed_index[listed[li]] = int32_t(li);
    pool.resize(listed.size() * cells * per);
    std::vector<uint16_t> count(listed.size() * cells, 0);  // samples <= 1000
    col.stats_.traced_samples =
        detail::shared_samples(grid, listed, listed_index, shaft_selected, cell_shafts, origins, trace, config,
                               pool, count);
  }
  const bool chunked = pool.empty() && tree.size() > 0;
  std::atomic<int64_t> chunk_trace_ns{0};
  col.stats_.samples_ms = ms_since(t_samples);

  // Chunks of up to kChunk listed voxels: their sample rays are traced cell-major first.
  constexpr size_t kChunk = 32;
  const VoxelListMaker::Context context{tree, grid, config, groups, group_shafts, cell_shafts, shaft_selected};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, listed.size(), kChunk / 2), [&](const auto& range) {
    VoxelListMaker maker(context);
    std::vector<PooledSample> chunk_pool;
    size_t chunk_begin = 0, chunk_end = 0;
    for (size_t li = range.begin(); li != range.end(); ++li) {
      if (chunked && li >= chunk_end) {
        const auto t0 = SteadyClock::now();
        chunk_begin = li;
        chunk_end = std::min(range.end(), li + kChunk);
        detail::cell_major_samples(grid, listed, chunk_begin, chunk_end, shaft_selected, origins, trace, config,
                                   chunk_pool);
        chunk_trace_ns += std::chrono::duration_cast<std::chrono::nanoseconds>(SteadyClock::now() - t0).count();
      }
      auto samples_of = [&](uint32_t cell) {
        return chunked ? chunk_pool.data() + (cell * (chunk_end - chunk_begin) + (li - chunk_begin)) * per
                       : pool.data() + (cell * listed.size() + li) * per;
      };
      maker.make(listed[li], samples_of, out[li]);
    }
  });

  const double lists_ms = ms_since(t_lists);
  if (chunked) col.stats_.samples_ms = double(chunk_trace_ns.load()) * 1e-6;
  const auto t_pack = SteadyClock::now();
  col.pack(tree, listed, out, config.dedup);
  ShaftStats& st = col.stats_;
  st.select_ms = select_ms;
  st.lists_ms = lists_ms;
  st.pack_ms = ms_since(t_pack);
  st.build_rounds = 1;
  st.build_ms = ms_since(t_start);
  return col;
}

}  // namespace rayscout
