// Shaft selection: see shaft_selection.h.
#include "shaft_selection.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "rayscout/core/input_error.h"

namespace rayscout::detail {
namespace {

/// Voxels whose box meets a triangle's box and plane (a cheap conservative overlap).
std::vector<uint8_t> occupied_voxels(const ShaftGrid& grid, std::span<const Triangle> tris) {
  std::vector<uint8_t> occ(grid.voxel_count(), 0);
  for (const Triangle& t : tris) {
    const Bounds3 tb = t.bounds();
    const Vec3 n = t.normal();
    const ShaftGrid::VoxelBlock block = grid.block(tb);
    const bool small = block.extra_layers() <= 1;
    grid.for_each_voxel(block, [&](uint32_t v) {
      if (occ[v]) return;
      if (!small) {
        // Plane test with a generous margin: rejects voxels far from a big slanted triangle.
        const Bounds3 vb = grid.voxel_box(v);
        const Vec3 c = vb.center(), h = vb.diagonal() * 0.5f;
        const double dist = std::fabs(double(dot(n, c - t.v0)));
        const double reach = std::fabs(double(n.x) * h.x) + std::fabs(double(n.y) * h.y) +
                             std::fabs(double(n.z) * h.z);
        if (dist > reach * 1.01 + 1e-6 * length(n) * length(h)) return;
      }
      occ[v] = 1;
    });
  }
  return occ;
}

}  // namespace

Selection select_shafts(const ShaftGrid& grid, std::span<const Triangle> tris, const RayBatch& sample_rays,
                        const ShaftConfig& config) {
  const uint32_t cells = grid.cells_per_voxel();
  const size_t nvox = grid.voxel_count();
  Selection sel;
  sel.voxel_listed.assign(nvox, 0);
  if (config.select == ShaftSelect::Occupied) {
    sel.voxel_listed = occupied_voxels(grid, tris);
    sel.shafts = size_t(std::count(sel.voxel_listed.begin(), sel.voxel_listed.end(), 1)) * cells;
    return sel;
  }
  // Camera, CameraVoxels: count the pre-pass rays per shaft (or per voxel), then list the most
  // used until config.coverage of the classified rays is covered.
  const bool by_voxel = config.select == ShaftSelect::CameraVoxels;
  std::unordered_map<uint64_t, uint32_t> counts;
  size_t classified = 0;
  for (size_t i = 0; i < sample_rays.size(); ++i) {
    ShaftCoord c;
    if (!grid.classify(sample_rays[i], c)) continue;
    ++counts[by_voxel ? uint64_t(c.voxel) : uint64_t(c.voxel) * cells + c.cell];
    ++classified;
  }
  std::vector<std::pair<uint32_t, uint64_t>> order;
  for (const auto& [id, n] : counts) order.push_back({n, id});
  std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) {
    return a.first > b.first || (a.first == b.first && a.second < b.second);
  });
  if (!by_voxel) sel.shaft_selected.assign(nvox * cells, 0);
  size_t covered = 0;
  for (const auto& [n, id] : order) {
    if (double(covered) >= config.coverage * double(classified)) break;
    covered += n;
    if (by_voxel) {
      sel.voxel_listed[id] = 1;
      sel.shafts += cells;
    } else {
      sel.shaft_selected[id] = 1;
      sel.voxel_listed[id / cells] = 1;
      ++sel.shafts;
    }
  }
  return sel;
}

}  // namespace rayscout::detail
