// ShaftGrid: resolution from a voxel count, voxel boxes, cells and the entry-point clip.
#include "rayscout/shafts/shaft_grid.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace rayscout {

ShaftGrid::ShaftGrid(const Bounds3& box, std::array<int, 3> res, int dir_res)
    : box_(box), res_(res), dir_res_(std::max(1, dir_res)) {
  for (int a = 0; a < 3; ++a) {
    res_[a] = std::max(1, res_[a]);
    const float extent = box_.hi[a] - box_.lo[a];
    size_[a] = extent / float(res_[a]);
    inv_size_[a] = size_[a] > 0.0f ? 1.0f / size_[a] : 0.0f;
  }
  const Vec3 d = box_.diagonal();
  diagonal_ = std::sqrt(double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z);
}

std::array<int, 3> ShaftGrid::cubical_resolution(const Bounds3& box, double voxels) {
  const Vec3 d = box.diagonal();
  const float longest = max_component(d);
  if (!(longest > 0.0f)) return {1, 1, 1};
  // Axes thinner than 1/1000 of the longest count as flat: one voxel layer.
  double volume = 1.0;
  int dims = 0;
  for (int a = 0; a < 3; ++a)
    if (d[a] > 1e-3f * longest) { volume *= d[a]; ++dims; }
  const double side = std::pow(volume / std::max(1.0, voxels), 1.0 / dims);
  std::array<int, 3> res{1, 1, 1};
  for (int a = 0; a < 3; ++a)
    if (d[a] > 1e-3f * longest) res[a] = std::clamp(int(std::lround(d[a] / side)), 1, 4096);
  return res;
}

Bounds3 ShaftGrid::voxel_box(uint32_t voxel) const {
  const std::array<int, 3> idx = voxel_coords(voxel);
  Bounds3 b;
  for (int a = 0; a < 3; ++a) {
    b.lo[a] = box_.lo[a] + float(idx[a]) * size_[a];
    b.hi[a] = idx[a] + 1 == res_[a] ? box_.hi[a] : box_.lo[a] + float(idx[a] + 1) * size_[a];
  }
  return b;
}

ShaftGrid::CellRange ShaftGrid::cell_range(uint32_t cell) const {
  const uint32_t d = uint32_t(dir_res_);
  const uint32_t iu = cell % d, iv = (cell / d) % d, face = cell / (d * d);
  const double step = 2.0 / dir_res_;
  return {int(face / 2), face % 2 ? -1 : 1, -1.0 + step * iu, -1.0 + step * (iu + 1),
          -1.0 + step * iv, -1.0 + step * (iv + 1)};
}

Vec3 ShaftGrid::face_direction(const CellRange& c, double u, double v) {
  Vec3 dir;
  const auto [ua, va] = face_axes(c.axis);
  dir[c.axis] = float(c.sign);
  dir[ua] = float(u);
  dir[va] = float(v);
  return dir;
}

bool ShaftGrid::classify_outside(const Ray& ray, ShaftCoord& out) const {
  if (!is_finite(ray.org) || !is_finite(ray.dir) || !(max_component(abs(ray.dir)) >= FLT_MIN)) return false;
  double t0 = 0.0, t1 = std::numeric_limits<double>::infinity(), dist2 = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double o = ray.org[a], d = ray.dir[a], lo = box_.lo[a], hi = box_.hi[a];
    const double gap = o < lo ? lo - o : (o > hi ? o - hi : 0.0);
    dist2 += gap * gap;
    if (d == 0.0) {
      if (o < lo || o > hi) return false;
      continue;
    }
    double ta = (lo - o) / d, tb = (hi - o) / d;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (dist2 > kFarFactor * kFarFactor * diagonal_ * diagonal_) return false;
  if (t0 > t1) return false;  // misses the box: the root test rejects it at once
  int idx[3];
  for (int a = 0; a < 3; ++a) {
    const double p = std::clamp(double(ray.org[a]) + t0 * double(ray.dir[a]), double(box_.lo[a]),
                                double(box_.hi[a]));
    const int i = int((p - box_.lo[a]) * double(inv_size_[a]));
    idx[a] = std::clamp(i, 0, res_[a] - 1);
  }
  out.voxel = voxel_id(idx[0], idx[1], idx[2]);
  out.cell = dir_cell(ray.dir);
  return true;
}

}  // namespace rayscout
