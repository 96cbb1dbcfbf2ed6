// Polygon triangulation of the OBJ and PLY readers: fans, and ear clipping for concave polygons.
#include "polygon.h"

#include <array>
#include <cmath>

namespace rayscout::detail {
namespace {

struct Point2 {
  double u, v;
};

// Twice the signed area of triangle (a, b, c): > 0 when it turns counter-clockwise.
double orient(const Point2& a, const Point2& b, const Point2& c) {
  return (b.u - a.u) * (c.v - a.v) - (b.v - a.v) * (c.u - a.u);
}

// The polygon's corners projected onto the plane of its largest Newell-normal component, mirrored
// where needed so that the polygon turns counter-clockwise; empty when the normal is zero.
std::vector<Point2> project(const std::vector<Vec3>& p) {
  double n[3] = {0, 0, 0};
  for (size_t i = 0; i < p.size(); ++i) {
    const Vec3& a = p[i];
    const Vec3& b = p[(i + 1) % p.size()];
    n[0] += (double(a.y) - b.y) * (double(a.z) + b.z);
    n[1] += (double(a.z) - b.z) * (double(a.x) + b.x);
    n[2] += (double(a.x) - b.x) * (double(a.y) + b.y);
  }
  const int axis = std::fabs(n[0]) >= std::fabs(n[1]) && std::fabs(n[0]) >= std::fabs(n[2]) ? 0
                   : std::fabs(n[1]) >= std::fabs(n[2])                                      ? 1
                                                                                             : 2;
  if (n[axis] == 0) return {};
  const double flip = n[axis] > 0 ? 1.0 : -1.0;
  std::vector<Point2> q;
  q.reserve(p.size());
  for (const Vec3& a : p) {
    const double x = a.x, y = a.y, z = a.z;
    // (y, z), (z, x), (x, y): counter-clockwise seen along +axis.
    q.push_back(axis == 0 ? Point2{flip * y, z} : axis == 1 ? Point2{flip * z, x} : Point2{flip * x, y});
  }
  return q;
}

// Ear clipping (Meisters 1975): cuts off a convex corner whose triangle holds no other corner,
// until three are left. A polygon without such a corner (self-intersecting, or made so by rounding)
// gets its first convex corner cut, else any: n - 2 triangles whatever the input.
void ear_clip(const std::vector<Point2>& q, const std::vector<uint32_t>& index, std::array<uint32_t, 3>* out) {
  const size_t n = q.size();
  std::vector<size_t> prev(n), next(n);
  for (size_t i = 0; i < n; ++i) {
    prev[i] = (i + n - 1) % n;
    next[i] = (i + 1) % n;
  }
  const auto same = [&](size_t a, size_t b) { return q[a].u == q[b].u && q[a].v == q[b].v; };
  const auto is_ear = [&](size_t b) {
    const size_t a = prev[b], c = next[b];
    if (!(orient(q[a], q[b], q[c]) > 0)) return false;
    for (size_t p = next[c]; p != a; p = next[p]) {
      if (same(p, a) || same(p, b) || same(p, c)) continue;  // a corner repeated (a bridged hole)
      if (orient(q[a], q[b], q[p]) >= 0 && orient(q[b], q[c], q[p]) >= 0 && orient(q[c], q[a], q[p]) >= 0) return false;
    }
    return true;
  };
  size_t at = 0;
  for (size_t left = n; left > 3; --left) {
    size_t ear = SIZE_MAX, convex = SIZE_MAX;
    size_t b = at;
    for (size_t k = 0; k < left && ear == SIZE_MAX; ++k, b = next[b]) {
      if (is_ear(b)) ear = b;
      else if (convex == SIZE_MAX && orient(q[prev[b]], q[b], q[next[b]]) > 0) convex = b;
    }
    if (ear == SIZE_MAX) ear = convex != SIZE_MAX ? convex : at;
    *out++ = {index[prev[ear]], index[ear], index[next[ear]]};
    next[prev[ear]] = next[ear];
    prev[next[ear]] = prev[ear];
    at = next[ear];
  }
  *out = {index[prev[at]], index[at], index[next[at]]};
}

}  // namespace

void add_polygon(const std::vector<uint32_t>& poly, uint32_t material, Mesh& mesh, std::vector<FannedPolygon>& polygons) {
  if (poly.size() > 3) polygons.push_back({mesh.faces.size(), uint32_t(poly.size())});
  for (size_t k = 1; k + 1 < poly.size(); ++k) {
    mesh.faces.push_back({poly[0], poly[k], poly[k + 1]});
    mesh.face_materials.push_back(material);
  }
}

size_t ear_clip_concave(Mesh& mesh, const std::vector<FannedPolygon>& polygons) {
  size_t kept = 0;
  std::vector<uint32_t> index;
  std::vector<Vec3> corners;
  for (const FannedPolygon& pg : polygons) {
    // The fan (v0 v1 v2), (v0 v2 v3), ... holds v0, v1, then each triangle's last corner.
    std::array<uint32_t, 3>* fan = &mesh.faces[pg.first];
    index.assign({fan[0][0], fan[0][1]});
    for (uint32_t k = 0; k + 2 < pg.vertices; ++k) index.push_back(fan[k][2]);
    corners.clear();
    for (uint32_t i : index) corners.push_back(mesh.positions[i]);
    const std::vector<Point2> q = project(corners);
    if (q.empty()) continue;  // no area: its triangles are dropped as zero-area anyway
    // A fan triangle turned against the polygon covers area outside it; all turned with it tile it.
    bool fan_tiles = true;
    for (size_t k = 1; k + 1 < q.size() && fan_tiles; ++k) fan_tiles = orient(q[0], q[k], q[k + 1]) >= 0;
    if (fan_tiles) continue;
    if (q.size() > kMaxEarClipVertices) {
      ++kept;
      continue;
    }
    ear_clip(q, index, fan);
  }
  return kept;
}

std::string concave_fans_kept(const std::string& file, size_t kept) {
  return file + ": " + std::to_string(kept) + " concave polygon" + (kept == 1 ? "" : "s") + " of more than " +
         std::to_string(kMaxEarClipVertices) + " vertices fan-triangulated (the fan covers area outside " +
         (kept == 1 ? "it" : "them") + ")";
}

}  // namespace rayscout::detail
