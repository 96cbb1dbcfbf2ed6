// Sample rays of shafts: see shaft_samples.h.
#include "shaft_samples.h"

#include <array>
#include <atomic>
#include <cmath>

#include <tbb/parallel_for.h>

namespace rayscout::detail {

size_t shared_samples(const ShaftGrid& grid, const std::vector<uint32_t>& listed,
                      const std::vector<int32_t>& listed_index, const std::vector<uint8_t>& shaft_selected,
                      const std::vector<Shaft>& cell_shafts, const VoxelSurfaces* surfaces,
                      const ShaftCollection::TraceFn& trace, const ShaftConfig& config,
                      std::vector<PooledSample>& pool, std::vector<uint16_t>& count) {
  const uint32_t cells = grid.cells_per_voxel();
  const int per = config.samples.value();
  const auto res = grid.res();
  const Bounds3& box = grid.box();
  Vec3 size;
  for (int a = 0; a < 3; ++a) size[a] = (box.hi[a] - box.lo[a]) / float(res[a]);
  // Listed voxels upstream first for each of the 6 face directions (stable: by voxel id within a layer).
  std::array<std::vector<uint32_t>, 6> orders;
  for (int face = 0; face < 6; ++face) {
    const int axis = face / 2;
    const bool positive = face % 2 == 0;
    std::vector<std::pair<int, uint32_t>> keyed(listed.size());
    for (uint32_t li = 0; li < listed.size(); ++li) {
      const uint32_t v = listed[li];
      const std::array<int, 3> idx = grid.voxel_coords(v);
      keyed[li] = {positive ? idx[axis] : res[axis] - 1 - idx[axis], li};
    }
    std::stable_sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [layer, li] : keyed) orders[size_t(face)].push_back(li);
  }
  std::atomic<size_t> traced{0};
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, cells, 1), [&](const auto& range) {
    size_t task_traced = 0;
    for (uint32_t cell = range.begin(); cell != range.end(); ++cell) {
      const ShaftGrid::CellRange cr = grid.cell_range(cell);
      const std::vector<uint32_t>& order = orders[size_t(2 * cr.axis + (cr.sign > 0 ? 0 : 1))];
      // Cell-major layout: this task's deposits stay within one compact region of the pool.
      auto wants = [&](uint32_t li) {
        const size_t k = size_t(cell) * listed.size() + li;
        return count[k] < per && (shaft_selected.empty() || shaft_selected[uint64_t(listed[li]) * cells + cell]);
      };
      auto deposit = [&](uint32_t li, const Vec3& org, const Vec3& dir, float hit_t) {
        const size_t k = size_t(cell) * listed.size() + li;
        pool[k * size_t(per) + count[k]] = {{org.x, org.y, org.z}, {1.0f / dir.x, 1.0f / dir.y, 1.0f / dir.z}, hit_t};
        ++count[k];
      };
      for (const uint32_t li : order) {
        if (!wants(li)) continue;
        const uint32_t v = listed[li];
        const Bounds3 vbox = grid.voxel_box(v);
        const ShaftGrid::CellRange& crange = cell_shafts[cell].cell();
        SampleStream stream(uint64_t(v) * cells + cell, config);
        for (int k = 0; wants(li); ++k) {
          float rnd[5];
          stream.next(k, rnd);
          const Ray ray = sample_ray(vbox, crange, rnd, surfaces, v);
          const float hit_t = trace(ray);
          ++task_traced;
          deposit(li, ray.org, ray.dir, hit_t);
          // 3D-DDA through the grid up to the hit.
          std::array<int, 3> idx = grid.voxel_coords(v);
          float t_next[3], t_delta[3];
          int step[3];
          for (int a = 0; a < 3; ++a) {
            const float d = ray.dir[a];
            step[a] = d > 0.0f ? 1 : -1;
            if (d == 0.0f || !(size[a] > 0.0f)) {
              t_next[a] = t_delta[a] = kInfinity;
              continue;
            }
            const float bound = box.lo[a] + float(idx[a] + (d > 0.0f ? 1 : 0)) * size[a];
            t_next[a] = std::max(0.0f, (bound - ray.org[a]) / d);
            t_delta[a] = size[a] / std::fabs(d);
          }
          for (int guard = 0; guard < res[0] + res[1] + res[2] + 3; ++guard) {
            const int a = t_next[0] <= t_next[1] && t_next[0] <= t_next[2] ? 0 : (t_next[1] <= t_next[2] ? 1 : 2);
            const float t_in = t_next[a];
            if (!(t_in < hit_t)) break;
            idx[a] += step[a];
            if (idx[a] < 0 || idx[a] >= res[a]) break;
            t_next[a] += t_delta[a];
            const int32_t wi = listed_index[grid.voxel_id(idx[0], idx[1], idx[2])];
            if (wi < 0 || !wants(uint32_t(wi))) continue;
            const float t_out = std::min(std::min(t_next[0], t_next[1]), std::min(t_next[2], hit_t));
            const float t = t_in + (t_out - t_in) * stream.uniform();
            deposit(uint32_t(wi), ray.org + ray.dir * t, ray.dir, hit_t - t);
          }
        }
      }
    }
    traced += task_traced;
  });
  return traced;
}

void cell_major_samples(const ShaftGrid& grid, const std::vector<uint32_t>& listed, size_t l0, size_t l1,
                        const std::vector<uint8_t>& shaft_selected, const VoxelSurfaces* surfaces,
                        const ShaftCollection::TraceFn& trace, const ShaftConfig& config,
                        std::vector<PooledSample>& pool) {
  const uint32_t cells = grid.cells_per_voxel();
  const size_t per = size_t(config.samples.value()), n = l1 - l0;
  pool.resize(size_t(cells) * n * per);
  for (uint32_t cell = 0; cell < cells; ++cell) {
    const ShaftGrid::CellRange crange = grid.cell_range(cell);
    for (size_t li = l0; li < l1; ++li) {
      const uint32_t v = listed[li];
      const uint64_t sid = uint64_t(v) * cells + cell;
      if (!shaft_selected.empty() && !shaft_selected[sid]) continue;
      PooledSample* out = pool.data() + (size_t(cell) * n + (li - l0)) * per;
      trace_own_samples(grid.voxel_box(v), crange, sid, surfaces, v, trace, config, [&](size_t s, const Ray& ray, float hit_t) {
        out[s] = {{ray.org.x, ray.org.y, ray.org.z}, {1.0f / ray.dir.x, 1.0f / ray.dir.y, 1.0f / ray.dir.z}, hit_t};
      });
    }
  }
}

}  // namespace rayscout::detail
