// Sample rays of shafts: see shaft_samples.h.
#include "shaft_samples.h"

#include <array>
#include <atomic>
#include <cmath>

#include <tbb/parallel_for.h>

namespace rayscout::detail {

namespace {

/// For each of the 6 face directions (face = 2 axis + negative), the listed voxels (indices
/// into listed) upstream first: by layer along the face's axis, in its direction; stable, so
/// by voxel id within a layer.
std::array<std::vector<uint32_t>, 6> upstream_orders(const ShaftGrid& grid, const std::vector<uint32_t>& listed) {
  std::array<std::vector<uint32_t>, 6> orders;
  const auto res = grid.res();
  for (int face = 0; face < 6; ++face) {
    const int axis = face / 2;
    const bool positive = face % 2 == 0;
    std::vector<std::pair<int, uint32_t>> keyed(listed.size());
    for (uint32_t li = 0; li < listed.size(); ++li) {
      const std::array<int, 3> idx = grid.voxel_coords(listed[li]);
      keyed[li] = {positive ? idx[axis] : res[axis] - 1 - idx[axis], li};
    }
    std::stable_sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [layer, li] : keyed) orders[size_t(face)].push_back(li);
  }
  return orders;
}

/// 3D-DDA (Amanatides & Woo 1987) of a ray from inside `voxel`: calls visit(v, t_in, t_out)
/// for every later voxel v of the grid it enters before hit_t, [t_in, t_out) the part of the
/// ray in v (t_out clipped to hit_t).
template <class Visit>
void for_each_voxel_crossed(const ShaftGrid& grid, const Ray& ray, uint32_t voxel, float hit_t, Visit visit) {
  const auto res = grid.res();
  const Bounds3& box = grid.box();
  const Vec3 size = grid.voxel_size();
  std::array<int, 3> idx = grid.voxel_coords(voxel);
  float t_next[3], t_delta[3];  // where the ray leaves the current layer of each axis; a layer's length
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
  // A ray crosses at most res[0] + res[1] + res[2] faces; the guard only bounds rounding.
  for (int guard = 0; guard < res[0] + res[1] + res[2] + 3; ++guard) {
    const int a = t_next[0] <= t_next[1] && t_next[0] <= t_next[2] ? 0 : (t_next[1] <= t_next[2] ? 1 : 2);
    const float t_in = t_next[a];
    if (!(t_in < hit_t)) return;
    idx[a] += step[a];
    if (idx[a] < 0 || idx[a] >= res[a]) return;
    t_next[a] += t_delta[a];
    const float t_out = std::min(std::min(t_next[0], t_next[1]), std::min(t_next[2], hit_t));
    visit(grid.voxel_id(idx[0], idx[1], idx[2]), t_in, t_out);
  }
}

/// The shared pool being filled: per shaft (cell, listed voxel li) up to `per` sample rays at
/// pool[(cell * listed + li) * per ...], count[cell * listed + li] of them stored. Cell-major,
/// so that the task of one cell deposits within one compact region.
struct SharedPool {
  const std::vector<uint32_t>& listed;
  const std::vector<uint8_t>& shaft_selected;
  uint32_t cells;
  int per;
  std::vector<PooledSample>& pool;
  std::vector<uint16_t>& count;

  /// Whether the shaft is selected and still short of samples.
  bool wants(uint32_t cell, uint32_t li) const {
    return count[shaft(cell, li)] < per &&
           (shaft_selected.empty() || shaft_selected[uint64_t(listed[li]) * cells + cell]);
  }
  void deposit(uint32_t cell, uint32_t li, const Vec3& org, const Vec3& dir, float hit_t) {
    const size_t k = shaft(cell, li);
    pool[k * size_t(per) + count[k]] = {{org.x, org.y, org.z}, {1.0f / dir.x, 1.0f / dir.y, 1.0f / dir.z}, hit_t};
    ++count[k];
  }

 private:
  size_t shaft(uint32_t cell, uint32_t li) const { return size_t(cell) * listed.size() + li; }
};

}  // namespace

size_t shared_samples(const ShaftGrid& grid, const std::vector<uint32_t>& listed,
                      const std::vector<int32_t>& listed_index, const std::vector<uint8_t>& shaft_selected,
                      const VoxelSurfaces* surfaces, const ShaftCollection::TraceFn& trace, const ShaftConfig& config,
                      std::vector<PooledSample>& pool, std::vector<uint16_t>& count) {
  const uint32_t cells = grid.cells_per_voxel();
  const std::array<std::vector<uint32_t>, 6> orders = upstream_orders(grid, listed);
  SharedPool shared{listed, shaft_selected, cells, config.samples.value(), pool, count};
  std::atomic<size_t> traced{0};
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, cells, 1), [&](const auto& range) {
    size_t task_traced = 0;
    for (uint32_t cell = range.begin(); cell != range.end(); ++cell) {
      const ShaftGrid::CellRange cr = grid.cell_range(cell);
      for (const uint32_t li : orders[size_t(2 * cr.axis + (cr.sign > 0 ? 0 : 1))]) {
        if (!shared.wants(cell, li)) continue;
        // A voxel still short of samples shoots its own (the same stream as its own samples);
        // each also serves every later listed voxel it crosses before its hit, from an origin
        // uniform on its chord through that voxel.
        const uint32_t v = listed[li];
        const Bounds3 vbox = grid.voxel_box(v);
        SampleStream stream(uint64_t(v) * cells + cell, config);
        for (int k = 0; shared.wants(cell, li); ++k) {
          float rnd[5];
          stream.next(k, rnd);
          const Ray ray = sample_ray(vbox, cr, rnd, surfaces, v);
          const float hit_t = trace(ray);
          ++task_traced;
          shared.deposit(cell, li, ray.org, ray.dir, hit_t);
          for_each_voxel_crossed(grid, ray, v, hit_t, [&](uint32_t w, float t_in, float t_out) {
            const int32_t wi = listed_index[w];
            if (wi < 0 || !shared.wants(cell, uint32_t(wi))) return;
            const float t = t_in + (t_out - t_in) * stream.uniform();
            shared.deposit(cell, uint32_t(wi), ray.org + ray.dir * t, ray.dir, hit_t - t);
          });
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
