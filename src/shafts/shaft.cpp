// Shaft: separating axes of voxel (+) cone, and sample rays inside the shaft.
#include "shaft.h"

#include <cmath>

namespace rayscout {
namespace {

using D3 = std::array<double, 3>;

D3 cross3(const D3& a, const D3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot3(const D3& a, const D3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

}  // namespace

Shaft::Shaft(const ShaftGrid& grid, ShaftCoord coord) : Shaft(grid, coord.voxel, grid.cell_range(coord.cell)) {}

void Shaft::set_voxel(const ShaftGrid& grid, uint32_t voxel) {
  voxel_ = grid.voxel_box(voxel);
  const Bounds3& g = grid.box();
  const Vec3 gd = g.diagonal();
  const double diag = std::sqrt(double(gd.x) * gd.x + double(gd.y) * gd.y + double(gd.z) * gd.z);
  // The padding covers the triangle test's rounding (kPadSpace of the diagonal) and where
  // classification meets float voxel planes: an outside ray's entry point (clipped in double)
  // and an origin beside a voxel face may lie about an ulp of the coordinates outside them,
  // which far from the world origin exceeds kPadSpace (0.027 at y = 1e6 in a 4-unit scene).
  const double coords = double(max_component(max(abs(g.lo), abs(g.hi))));
  const double pad = std::max(kPadSpace * diag, 4.0 * coords * std::ldexp(1.0, -23));
  for (int k = 0; k < 3; ++k) {
    vlo_[k] = double(voxel_.lo[k]) - pad;
    vhi_[k] = double(voxel_.hi[k]) + pad;
    fvlo_[k] = float(vlo_[k]);
    fvhi_[k] = float(vhi_[k]);
    if (double(fvlo_[k]) > vlo_[k]) fvlo_[k] = std::nextafter(fvlo_[k], -kInfinity);
    if (double(fvhi_[k]) < vhi_[k]) fvhi_[k] = std::nextafter(fvhi_[k], kInfinity);
  }
  // The float support value sums 6 products of unit axes with the components of B (-) V,
  // differences of a box and a padded voxel coordinate, each rounded to half an ulp of its
  // result. Boxes come from the BVH whose root box is the grid box and holds every node box
  // (WideNode keeps its child boxes in float, unquantised), so the components stay below
  // reach = 2 (diagonal + padding), and the rounding error below 16 ulps of 2 reach. 64 ulps, about 4e-6 of it, is far below the
  // padding. The coordinates themselves do not enter: the tolerance grew with them before,
  // and culling faded with the distance from the world origin (a 10-unit soup at 1e5 saved
  // 21 % of the steps, at the origin 42 %).
  const double reach = 2.0 * (diag + pad);
  tol_ = float(2.0 * reach * 64.0 * std::ldexp(1.0, -24));
}

Shaft::Shaft(const ShaftGrid& grid, uint32_t voxel, const ShaftGrid::CellRange& cell) {
  set_voxel(grid, voxel);
  cell_ = cell;
  // Cone edges: the four corner directions of the padded cell.
  const auto [ua, va] = ShaftGrid::face_axes(cell_.axis);
  const double us[2] = {cell_.u0 - kPadDir, cell_.u1 + kPadDir};
  const double vs[2] = {cell_.v0 - kPadDir, cell_.v1 + kPadDir};
  std::array<D3, 4> edges;
  const int corner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};  // cyclic order around the cone
  for (int i = 0; i < 4; ++i) {
    D3 e{};
    e[cell_.axis] = cell_.sign;
    e[ua] = us[corner[i][0]];
    e[va] = vs[corner[i][1]];
    edges[i] = e;
  }
  std::array<D3, 19> candidates;
  int nc = 0;
  for (int k = 0; k < 3; ++k) {
    D3 n{};
    n[k] = 1.0;
    candidates[size_t(nc++)] = n;  // back / outer voxel faces
    for (const auto& e : edges) candidates[size_t(nc++)] = cross3(e, n);  // bevel planes
  }
  for (int i = 0; i < 4; ++i) candidates[size_t(nc++)] = cross3(edges[i], edges[(i + 1) % 4]);  // sides
  for (int ci = 0; ci < nc; ++ci) {
    D3 n = candidates[size_t(ci)];
    const double len = std::sqrt(dot3(n, n));
    if (len < 1e-12) continue;
    for (auto& c : n) c /= len;
    // Keep an axis only when the whole cone projects on one side of it; dots within 1e-12
    // of zero count as zero (an edge lying in the plane).
    bool pos = true, neg = true;
    for (const auto& e : edges) {
      const double s = dot3(e, n);
      if (s < -1e-12) pos = false;
      if (s > 1e-12) neg = false;
    }
    if (neg && !pos)
      for (auto& c : n) c = -c;
    if (!(pos || neg)) continue;
    // Each side plane is a bevel plane: neighbouring edges differ in one face coordinate,
    // so cross(e_i, e_i+1) is a multiple of cross(e_i, that face axis). A repeated axis
    // decides nothing. So at most 3 faces + 12 bevels remain: one 16-slot row. (Were a
    // rounding to keep a 17th, dropping it would only cull less: still conservative.)
    const auto same = [&](const D3& m) { return dot3(m, n) > 1.0 - 1e-9; };
    if (axis_count_ < kAxes && std::none_of(axes_.begin(), axes_.begin() + axis_count_, same))
      axes_[size_t(axis_count_++)] = n;
  }
  // Float copies of the axes (rounding to float moves a unit axis by ~6e-8, far less than
  // the 1e-4 by which the real cone lies inside the padded cone's planes, so every float
  // axis still has the whole real cone on its positive side: a valid separating axis).
  for (int a = 0; a < axis_count_; ++a)
    for (int k = 0; k < 3; ++k) {
      const float c = float(axes_[size_t(a)][k]);
      pos_[k][a] = c > 0.0f ? c : 0.0f;
      neg_[k][a] = c < 0.0f ? c : 0.0f;
    }
  const Vec3 c = ShaftGrid::face_direction(cell_, 0.5 * (cell_.u0 + cell_.u1), 0.5 * (cell_.v0 + cell_.v1));
  center_dir_ = normalize(c);
}

Ray Shaft::sample_ray(const Bounds3& voxel, const ShaftGrid::CellRange& cell, const float rnd[5]) {
  Ray r;
  const Vec3 d = voxel.diagonal();
  r.org = voxel.lo + Vec3{d.x * rnd[0], d.y * rnd[1], d.z * rnd[2]};
  r.dir = normalize(ShaftGrid::face_direction(cell, cell.u0 + (cell.u1 - cell.u0) * rnd[3],
                                              cell.v0 + (cell.v1 - cell.v0) * rnd[4]));
  r.tmin = 0.0f;
  r.tmax = kInfinity;
  return r;
}

}  // namespace rayscout
