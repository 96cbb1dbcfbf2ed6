// ShaftCollection: occupancy, shaft selection, parallel list construction, deduplication and
// the memory-budget loop.
#include "rayscout/shafts/shaft_collection.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include <tbb/parallel_for.h>

#include "candidate_list.h"

namespace rayscout {
namespace {

uint64_t splitmix64(uint64_t& s) {
  uint64_t z = (s += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}
float uniform01(uint64_t& s) { return float(splitmix64(s) >> 40) * (1.0f / 16777216.0f); }

/// Voxels whose box meets a triangle's box and plane (a cheap conservative overlap).
std::vector<uint8_t> occupied_voxels(const ShaftGrid& grid, std::span<const Triangle> tris) {
  std::vector<uint8_t> occ(grid.voxel_count(), 0);
  const Bounds3& box = grid.box();
  const auto res = grid.res();
  Vec3 size;
  for (int a = 0; a < 3; ++a) size[a] = (box.hi[a] - box.lo[a]) / float(res[a]);
  auto index = [&](float p, int a) {
    if (!(size[a] > 0.0f)) return 0;
    return std::clamp(int(std::floor((p - box.lo[a]) / size[a])), 0, res[a] - 1);
  };
  for (const Triangle& t : tris) {
    const Bounds3 tb = t.bounds();
    const Vec3 n = t.normal();
    const int x0 = index(tb.lo.x, 0), x1 = index(tb.hi.x, 0);
    const int y0 = index(tb.lo.y, 1), y1 = index(tb.hi.y, 1);
    const int z0 = index(tb.lo.z, 2), z1 = index(tb.hi.z, 2);
    const bool small = (x1 - x0) + (y1 - y0) + (z1 - z0) <= 1;
    for (int z = z0; z <= z1; ++z)
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          const uint32_t v = grid.voxel_id(x, y, z);
          if (occ[v]) continue;
          if (!small) {
            // Plane test with a generous margin: rejects voxels far from a big slanted triangle.
            const Bounds3 vb = grid.voxel_box(v);
            const Vec3 c = vb.center(), h = vb.diagonal() * 0.5f;
            const double dist = std::fabs(double(dot(n, c - t.v0)));
            const double reach = std::fabs(double(n.x) * h.x) + std::fabs(double(n.y) * h.y) +
                                 std::fabs(double(n.z) * h.z);
            if (dist > reach * 1.01 + 1e-6 * length(n) * length(h)) continue;
          }
          occ[v] = 1;
        }
  }
  return occ;
}

}  // namespace

std::string ShaftStats::summary() const {
  std::ostringstream s;
  s << "grid " << res[0] << "x" << res[1] << "x" << res[2] << " voxels, d=" << dir_res << " ("
    << 6 * dir_res * dir_res << " cells/voxel); listed voxels " << listed_voxels << "/" << voxels
    << ", listed shafts " << listed_shafts << "/" << shafts << " (" << empty_lists << " reach nothing)\n"
    << "memory: lookup " << lookup_bytes / 1024.0 << " KiB + lists " << list_bytes / 1024.0
    << " KiB = " << memory_bytes() / 1048576.0 << " MiB (budget " << budget_bytes / 1048576.0
    << " MiB); dedup saved " << dedup_saved_bytes / 1024.0 << " KiB, " << unique_lists << " unique lists\n"
    << "lists: mean length " << mean_list << ", max " << max_list << "; overflow retries "
    << overflow_retries << ", fallbacks " << overflow_fallbacks << "\n"
    << "build " << build_ms << " ms in " << build_rounds << " round(s)";
  return s.str();
}

ShaftCollection ShaftCollection::build_grid(const TreeView& tree, const ShaftGrid& grid,
                                            std::span<const Triangle> tris, const TraceFn& trace,
                                            const RayBatch& sample_rays, const ShaftConfig& config) {
  const auto t_start = std::chrono::steady_clock::now();
  if (config.max_list < 1 || config.max_list > 31)
    throw InputError("shafts: max_list must be in 1..31 (got " + std::to_string(config.max_list) + ")");
  ShaftCollection col;
  col.grid_ = grid;
  const uint32_t cells = grid.cells_per_voxel();
  const size_t nvox = grid.voxel_count();
  if (nvox * cells >= (size_t(1) << 32) - 64)
    throw InputError("shafts: too many shafts (" + std::to_string(nvox * cells) + ")");

  // Which shafts get lists: a bitmap per listed voxel.
  std::vector<uint8_t> voxel_listed(nvox, 0);
  std::vector<uint8_t> shaft_selected;  // empty = every cell of a listed voxel
  if (config.select == "occupied") {
    voxel_listed = occupied_voxels(grid, tris);
  } else if (config.select == "camera") {
    std::unordered_map<uint64_t, uint32_t> counts;
    size_t classified = 0;
    for (size_t i = 0; i < sample_rays.size(); ++i) {
      ShaftCoord c;
      if (!grid.classify(sample_rays[i], c)) continue;
      ++counts[uint64_t(c.voxel) * cells + c.cell];
      ++classified;
    }
    std::vector<std::pair<uint32_t, uint64_t>> order;
    for (const auto& [id, n] : counts) order.push_back({n, id});
    std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) {
      return a.first > b.first || (a.first == b.first && a.second < b.second);
    });
    shaft_selected.assign(nvox * cells, 0);
    size_t covered = 0;
    for (const auto& [n, id] : order) {
      if (double(covered) >= config.coverage * double(classified)) break;
      covered += n;
      shaft_selected[id] = 1;
      voxel_listed[id / cells] = 1;
    }
  } else {
    throw InputError("shafts: select must be 'occupied' or 'camera' (got '" + config.select + "')");
  }

  std::vector<uint32_t> listed;
  for (uint32_t v = 0; v < nvox; ++v)
    if (voxel_listed[v]) listed.push_back(v);

  // Per listed voxel: for each cell, (status, list) where status 0 = no list, 1 = list,
  // 2 = reaches nothing; lists concatenated in `data`.
  struct VoxelLists {
    std::vector<uint8_t> status;
    std::vector<uint8_t> len;
    std::vector<uint32_t> data;
    size_t retries = 0, fallbacks = 0;
  };
  std::vector<VoxelLists> out(listed.size());
  const double min_prob = config.min_prob >= 0.0 ? config.min_prob : double(tree.arity - 1) / tree.arity;
  const int ns = std::max(0, config.samples);

  tbb::parallel_for(tbb::blocked_range<size_t>(0, listed.size(), 1), [&](const auto& range) {
    detail::ShaftSamples samples;
    std::vector<uint32_t> list;
    for (size_t li = range.begin(); li != range.end(); ++li) {
      const uint32_t voxel = listed[li];
      VoxelLists& vl = out[li];
      vl.status.assign(cells, 0);
      vl.len.assign(cells, 0);
      for (uint32_t cell = 0; cell < cells; ++cell) {
        const uint64_t sid = uint64_t(voxel) * cells + cell;
        if (!shaft_selected.empty() && !shaft_selected[sid]) continue;
        if (tree.size() == 0) { vl.status[cell] = 2; continue; }
        const Shaft shaft(grid, {voxel, cell});
        uint64_t rng = (uint64_t(config.seed) << 40) ^ (sid * 0x2545F4914F6CDD1Dull);
        samples.org.resize(ns);
        samples.inv_dir.resize(ns);
        samples.hit_t.resize(ns);
        for (int s = 0; s < ns; ++s) {
          float rnd[5];
          for (float& r : rnd) r = uniform01(rng);
          const Ray ray = shaft.sample_ray(rnd);
          samples.org[s] = ray.org;
          samples.inv_dir[s] = Vec3(1.0f / ray.dir.x, 1.0f / ray.dir.y, 1.0f / ray.dir.z);
          samples.hit_t[s] = trace(ray);
        }
        detail::CandidateListBuilder builder(tree, shaft, samples);
        bool ok = builder.build(min_prob, config.max_list, list);
        for (int i = 0; !ok && i < config.retries; ++i) {
          ++vl.retries;
          ok = builder.build(min_prob + double(i + 1) / 20.0, config.max_list, list);
        }
        if (!ok) {
          ++vl.fallbacks;
          list.clear();
          const uint32_t n = builder.cull_subtree(tree.root);
          if (n != detail::CandidateListBuilder::kNone) list.push_back(tree.ref[n]);
        }
        if (list.empty()) {
          vl.status[cell] = 2;
          continue;
        }
        vl.status[cell] = 1;
        vl.len[cell] = uint8_t(list.size());
        vl.data.insert(vl.data.end(), list.begin(), list.end());
      }
    }
  });

  // Serial packing with deduplication keeps offsets independent of the thread count.
  ShaftStats& st = col.stats_;
  st.res = grid.res();
  st.dir_res = grid.dir_res();
  st.voxels = nvox;
  st.shafts = nvox * cells;
  st.listed_voxels = listed.size();
  st.length_histogram.assign(32, 0);
  col.voxel_base_.assign(nvox, kNoVoxel);
  col.entries_.assign(listed.size() * cells, 0);
  struct ListHash {
    const std::vector<uint32_t>* area;
    size_t operator()(const std::pair<uint32_t, uint32_t>& k) const {
      uint64_t h = 1469598103934665603ull ^ k.second;
      for (uint32_t i = 0; i < k.second; ++i) h = (h ^ (*area)[k.first + i]) * 1099511628211ull;
      return size_t(h);
    }
  };
  struct ListEq {
    const std::vector<uint32_t>* area;
    bool operator()(const std::pair<uint32_t, uint32_t>& a, const std::pair<uint32_t, uint32_t>& b) const {
      return a.second == b.second &&
             std::equal(area->begin() + a.first, area->begin() + a.first + a.second, area->begin() + b.first);
    }
  };
  // Keys index col.lists_; a candidate is appended first and dropped again when a twin exists.
  std::unordered_map<std::pair<uint32_t, uint32_t>, uint32_t, ListHash, ListEq> known(
      1024, ListHash{&col.lists_}, ListEq{&col.lists_});
  size_t total_len = 0, nonempty = 0;
  for (size_t li = 0; li < listed.size(); ++li) {
    const VoxelLists& vl = out[li];
    const uint32_t base = uint32_t(li * cells);
    col.voxel_base_[listed[li]] = base;
    st.overflow_retries += vl.retries;
    st.overflow_fallbacks += vl.fallbacks;
    size_t pos = 0;
    for (uint32_t cell = 0; cell < cells; ++cell) {
      if (vl.status[cell] == 0) continue;
      ++st.listed_shafts;
      if (vl.status[cell] == 2) {
        ++st.empty_lists;
        col.entries_[base + cell] = kEmptyList;
        continue;
      }
      const uint32_t len = vl.len[cell];
      const uint32_t offset = uint32_t(col.lists_.size());
      col.lists_.insert(col.lists_.end(), vl.data.begin() + pos, vl.data.begin() + pos + len);
      pos += len;
      auto [it, inserted] = known.try_emplace({offset, len}, offset);
      if (!inserted) {
        col.lists_.resize(offset);
        st.dedup_saved_bytes += len * sizeof(uint32_t);
      }
      const uint32_t at = it->second;
      if (at >= (1u << 27)) throw InputError("shafts: list area exceeds 2^27 entries; lower the resolution");
      col.entries_[base + cell] = (at << 5) | len;
      ++st.length_histogram[len];
      total_len += len;
      ++nonempty;
      st.max_list = std::max(st.max_list, int(len));
    }
  }
  col.lists_.shrink_to_fit();
  st.unique_lists = known.size();
  st.mean_list = nonempty ? double(total_len) / double(nonempty) : 0.0;
  st.lookup_bytes = (col.voxel_base_.size() + col.entries_.size()) * sizeof(uint32_t);
  st.list_bytes = col.lists_.size() * sizeof(uint32_t);
  st.build_rounds = 1;
  st.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_start).count();
  return col;
}

ShaftCollection ShaftCollection::build(const TreeView& tree, const Bounds3& box, size_t bvh_bytes,
                                       std::span<const Triangle> tris, const TraceFn& trace,
                                       const RayBatch& sample_rays, const ShaftConfig& config) {
  const auto t_start = std::chrono::steady_clock::now();
  if (config.dir_res < 1 || config.dir_res > 64)
    throw InputError("shafts: dir_res must be in 1..64 (got " + std::to_string(config.dir_res) + ")");
  const size_t budget = config.budget_mib > 0.0 ? size_t(config.budget_mib * 1048576.0)
                                                : size_t(config.budget_rel * double(bvh_bytes));
  auto finish = [&](ShaftCollection col, int rounds) {
    col.stats_.build_rounds = rounds;
    col.stats_.budget_bytes = budget;
    col.stats_.build_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_start).count();
    return col;
  };
  if (config.voxels > 0) {
    const ShaftGrid grid(box, ShaftGrid::cubical_resolution(box, double(config.voxels)), config.dir_res);
    return finish(build_grid(tree, grid, tris, trace, sample_rays, config), 1);
  }
  const double cells = 6.0 * config.dir_res * config.dir_res;
  // First guess: occupancy of a probe grid, scaled as a surface (n^(2/3)), and 16 bytes per
  // listed shaft (4-byte entry + about 3 stored list entries after deduplication).
  const double probe_n = 4096;
  const ShaftGrid probe(box, ShaftGrid::cubical_resolution(box, probe_n), config.dir_res);
  double listed_frac = 1.0;
  if (config.select == "occupied") {
    const auto occ = occupied_voxels(probe, tris);
    listed_frac = double(std::count(occ.begin(), occ.end(), 1)) / double(probe.voxel_count());
  } else {
    listed_frac = 0.05;
  }
  double bytes_per_shaft = 16.0;
  auto estimate = [&](double n) {
    const double frac = std::min(1.0, listed_frac * std::pow(probe_n / n, 1.0 / 3.0));
    return 4.0 * n + frac * n * cells * bytes_per_shaft;
  };
  double lo = 1.0, hi = 1e8;
  for (int i = 0; i < 60; ++i) {
    const double mid = std::sqrt(lo * hi);
    (estimate(mid) <= 0.95 * double(budget) ? lo : hi) = mid;
  }
  double n = std::max(1.0, lo);
  ShaftCollection best;
  bool have_best = false;
  for (int round = 1; round <= 6; ++round) {
    const ShaftGrid grid(box, ShaftGrid::cubical_resolution(box, n), config.dir_res);
    ShaftCollection col = build_grid(tree, grid, tris, trace, sample_rays, config);
    const double mem = double(col.memory_bytes());
    if (mem <= double(budget)) {
      // Well under budget (the guess was pessimistic): one finer round at most.
      if (!have_best && mem < 0.6 * double(budget) && round == 1 && grid.voxel_count() > 1) {
        best = std::move(col);
        have_best = true;
        n *= std::pow(0.9 * double(budget) / std::max(mem, 1.0), 1.5);
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
