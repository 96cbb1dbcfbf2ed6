// Surface origins of sample rays: see voxel_surfaces.h.
#include "voxel_surfaces.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "rayscout/core/sampling.h"

namespace rayscout::detail {
namespace {

/// Sutherland-Hodgman: the part of polygon poly[0, n) with p[axis] >= bound (keep_above) or
/// <= bound; returns the new vertex count (a triangle clipped by 6 planes keeps <= 9).
int clip(const Vec3* poly, int n, int axis, float bound, bool keep_above, Vec3* out) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3& a = poly[i];
    const Vec3& b = poly[(i + 1) % n];
    const float da = keep_above ? a[axis] - bound : bound - a[axis];
    const float db = keep_above ? b[axis] - bound : bound - b[axis];
    if (da >= 0.0f) out[m++] = a;
    if ((da >= 0.0f) != (db >= 0.0f)) {
      Vec3 c = a + (b - a) * (da / (da - db));
      c[axis] = bound;  // exactly on the plane, whatever the rounding of the interpolation
      out[m++] = c;
    }
  }
  return m;
}

}  // namespace

VoxelSurfaces::VoxelSurfaces(const ShaftGrid& grid, std::span<const Triangle> tris, std::span<const uint32_t> voxels)
    : voxels_(voxels.begin(), voxels.end()) {
  std::sort(voxels_.begin(), voxels_.end());
  const Bounds3& box = grid.box();
  epsilon_ = std::max(1e-5f * length(box.diagonal()), 1e-30f);
  // The candidate triangles of each voxel: those whose box meets it.
  std::vector<std::vector<uint32_t>> candidates(voxels_.size());
  for (uint32_t t = 0; t < tris.size(); ++t) {
    const Bounds3 tb = tris[t].bounds();
    if (tb.empty() || !(tris[t].area() > 0.0f)) continue;
    grid.for_each_voxel(grid.block(tb), [&](uint32_t v) {
      if (const int64_t k = slot(v); k >= 0) candidates[size_t(k)].push_back(t);
    });
  }
  // Clip them to the voxel (in parallel), then concatenate.
  std::vector<std::vector<Piece>> per_voxel(voxels_.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, voxels_.size(), 8), [&](const auto& range) {
    for (size_t k = range.begin(); k != range.end(); ++k) {
      const Bounds3 vb = grid.voxel_box(voxels_[k]);
      for (const uint32_t t : candidates[k]) {
        const Triangle& tri = tris[t];
        const Bounds3 tb = tri.bounds();
        if (vb.contains(tb)) {
          per_voxel[k].push_back({tri.v0, tri.v1 - tri.v0, tri.v2 - tri.v0});
          continue;
        }
        Vec3 a[12] = {tri.v0, tri.v1, tri.v2}, b[12];
        int n = 3;
        for (int axis = 0; axis < 3 && n > 0; ++axis) {
          n = clip(a, n, axis, vb.lo[axis], true, b);
          n = clip(b, n, axis, vb.hi[axis], false, a);
        }
        for (int i = 1; i + 1 < n; ++i) per_voxel[k].push_back({a[0], a[i] - a[0], a[i + 1] - a[0]});
      }
    }
  });
  begin_.reserve(voxels_.size() + 1);
  std::vector<double> running;  // area of a voxel's pieces up to and including each
  for (size_t k = 0; k < voxels_.size(); ++k) {
    begin_.push_back(uint32_t(pieces_.size()));
    running.clear();
    double sum = 0.0;
    for (const Piece& p : per_voxel[k]) running.push_back(sum += 0.5 * double(length(cross(p.e1, p.e2))));
    if (!(sum > 0.0)) continue;
    pieces_.insert(pieces_.end(), per_voxel[k].begin(), per_voxel[k].end());
    for (const double r : running) cdf_.push_back(float(r / sum));
    cdf_.back() = 1.0f;
  }
  begin_.push_back(uint32_t(pieces_.size()));
}

int64_t VoxelSurfaces::slot(uint32_t voxel) const {
  const auto it = std::lower_bound(voxels_.begin(), voxels_.end(), voxel);
  return it != voxels_.end() && *it == voxel ? it - voxels_.begin() : -1;
}

bool VoxelSurfaces::sample(uint32_t voxel, const float rnd[3], Vec3& p) const {
  const int64_t slot_of_voxel = slot(voxel);
  if (slot_of_voxel < 0) return false;
  const size_t k = size_t(slot_of_voxel);
  const uint32_t b = begin_[k], e = begin_[k + 1];
  if (b == e) return false;
  const uint32_t i = uint32_t(std::upper_bound(cdf_.begin() + b, cdf_.begin() + e - 1, rnd[0]) - cdf_.begin());
  const Piece& piece = pieces_[i];
  const auto [b1, b2] = sample_triangle(rnd[1], rnd[2]);
  p = piece.v0 + piece.e1 * b1 + piece.e2 * b2;
  return true;
}

}  // namespace rayscout::detail
