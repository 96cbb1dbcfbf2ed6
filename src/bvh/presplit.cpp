// Triangle pre-splitting (Karras and Aila 2013, sec. 3) into tight reference boxes.
#include "presplit.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "binned_sah_builder.h"
#include "rayscout/core/input_error.h"

namespace rayscout::detail {
namespace {

// The finest level of the power-of-two grid tried (level 1 halves the scene): cells of 2^-23
// of the scene, near a float's relative precision.
constexpr int kFinestGridLevel = 23;

// Box of the part of tri on one side of the plane x[axis] = pos (left: <= pos), intersected
// with clip. Crossing points are padded outward by a few ulps so the box stays conservative.
Bounds3 clip_side(const Triangle& tri, int axis, float pos, bool left, const Bounds3& clip) {
  Bounds3 b;
  const Vec3 v[3] = {tri.v0, tri.v1, tri.v2};
  for (int i = 0; i < 3; ++i) {
    const Vec3& a = v[i];
    const Vec3& c = v[(i + 1) % 3];
    const bool a_in = left ? a[axis] <= pos : a[axis] >= pos;
    const bool c_in = left ? c[axis] <= pos : c[axis] >= pos;
    if (a_in) b.extend(a);
    if (a_in != c_in && a[axis] != c[axis]) {
      const float t = (pos - a[axis]) / (c[axis] - a[axis]);
      Vec3 p = a + (c - a) * t;
      for (int k = 0; k < 3; ++k) {
        constexpr float kRelativePad = 4.0f * std::numeric_limits<float>::epsilon();  // 2^-21
        const float pad = kRelativePad * std::max(std::fabs(a[k]), std::fabs(c[k]));
        Vec3 q = p;
        q[k] = p[k] - pad;
        b.extend(q);
        q[k] = p[k] + pad;
        b.extend(q);
      }
    }
  }
  if (b.empty()) return b;
  b.lo[axis] = left ? b.lo[axis] : std::max(b.lo[axis], pos);
  b.hi[axis] = left ? std::min(b.hi[axis], pos) : b.hi[axis];
  return {max(b.lo, clip.lo), min(b.hi, clip.hi)};
}

// The coarsest plane of the power-of-two grid over the scene that cuts box strictly inside:
// per axis, the grid line at or below the box's top at each level, coarse to fine; of axes
// whose planes are equally coarse, the lowest. False when there is none.
bool grid_plane(const Bounds3& box, const Bounds3& scene, int& axis, float& pos) {
  constexpr int kNone = kFinestGridLevel + 1;
  int best_level = kNone;
  const Vec3 ext = scene.diagonal();
  for (int a = 0; a < 3; ++a) {
    if (!(ext[a] > 0.0f) || !(box.hi[a] > box.lo[a])) continue;
    const float hi = (box.hi[a] - scene.lo[a]) / ext[a];
    // Only levels coarser than the best axis so far: an equal one keeps the lower axis.
    for (int level = 1; level < best_level; ++level) {
      const float cell = std::ldexp(1.0f, -level);
      const float k = std::floor(hi / cell);
      const float p = scene.lo[a] + k * cell * ext[a];
      if (p > box.lo[a] && p < box.hi[a]) {
        best_level = level;
        axis = a;
        pos = p;
        break;
      }
    }
  }
  return best_level < kNone;
}

// Writes n boxes covering tri within box into out (recursive binary splitting).
void split_into(const Triangle& tri, const Bounds3& box, uint32_t n, const Bounds3& scene, Bounds3* out) {
  int axis = 0;
  float pos = 0.0f;
  if (n == 1 || !grid_plane(box, scene, axis, pos)) {
    for (uint32_t i = 0; i < n; ++i) out[i] = box;  // no useful plane: repeat the box
    return;
  }
  const Bounds3 l = clip_side(tri, axis, pos, true, box), r = clip_side(tri, axis, pos, false, box);
  if (l.empty() || r.empty()) {
    split_into(tri, l.empty() ? r : l, n, scene, out);
    return;
  }
  const float wl = max_component(l.diagonal()), wr = max_component(r.diagonal());
  const float share = wl + wr > 0.0f ? wl / (wl + wr) : 0.5f;
  const uint32_t nl = std::clamp<uint32_t>(uint32_t(std::lround(float(n) * share)), 1u, n - 1);
  split_into(tri, l, nl, scene, out);
  split_into(tri, r, n - nl, scene, out + nl);
}

// Throws InputError naming the first triangle with an infinite or NaN vertex. NaN would make
// the bounds depend on the reduction order (SSE min and max are not symmetric in NaN), and
// infinity every enclosing node's SAH cost. The scene loader refuses both; this is for
// callers of the library.
void check_finite(std::span<const Triangle> tris) {
  auto finite = [](const Triangle& t) { return is_finite(t.v0) && is_finite(t.v1) && is_finite(t.v2); };
  const bool all_finite = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, tris.size(), 16384), true,
      [&](const auto& r, bool ok) {
        for (size_t i = r.begin(); i != r.end(); ++i) ok &= finite(tris[i]);
        return ok;
      },
      std::logical_and<>());
  if (all_finite) return;
  const auto bad = std::find_if_not(tris.begin(), tris.end(), finite);
  throw InputError("BVH: triangle " + std::to_string(bad - tris.begin()) + " has an infinite or NaN vertex");
}

// One reference per triangle, with its full box.
PrimReferences one_reference_each(std::span<const Triangle> tris) {
  PrimReferences refs;
  refs.boxes.resize(tris.size());
  refs.ref_tri.resize(tris.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, tris.size(), 4096), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) refs.boxes[i] = tris[i].bounds(), refs.ref_tri[i] = uint32_t(i);
  });
  return refs;
}

// Each triangle's claim on the budget (Karras and Aila's priority with exponent 0.3): the area
// its box wastes, box surface minus the triangle's two faces. Triangle boxes are recomputed
// where needed rather than kept: an array of them is fresh memory to fault in, which costs
// more than the few min/max operations.
std::vector<float> split_priorities(std::span<const Triangle> tris) {
  std::vector<float> priority(tris.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, tris.size(), 4096), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i)
      priority[i] = std::pow(std::max(0.0f, tris[i].bounds().surface_area() - 2.0f * tris[i].area()), 0.3f);
  });
  return priority;
}

// The scale s whose extra references, sum of min(max_extra, floor(priority s)), come closest
// to target from below. Karras and Aila find it by bisection: the plain target / sum of
// priorities gave a scene-dependent 4-45 % of the budget (Sponza 0.3 -> 3.5 %).
double budget_scale(const std::vector<float>& priority, double priority_sum, double target, double max_extra) {
  // Every term is a whole number, so the sum is exact in any order: summing in parallel
  // keeps the result (and the tree) independent of the thread count.
  auto extra_refs = [&](double s) {
    return tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, priority.size(), 8192), 0.0,
        [&](const auto& r, double sum) {
          for (size_t i = r.begin(); i != r.end(); ++i) sum += std::min(max_extra, std::floor(double(priority[i]) * s));
          return sum;
        },
        [](double a, double b) { return a + b; });
  };
  double lo = 0.0, hi = priority_sum > 0 ? target / priority_sum : 0.0;
  // Double until the target is bracketed; 1e30 stops a target no scale reaches (above
  // max_extra per triangle).
  while (hi > 0.0 && extra_refs(hi) < target && hi < 1e30) hi *= 2.0;
  constexpr int kHalvings = 25;
  for (int it = 0; it < kHalvings && hi > 0.0; ++it) {
    const double mid = 0.5 * (lo + hi);
    (extra_refs(mid) <= target ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace

std::vector<uint32_t> reference_offsets(std::span<const float> priority, double scale, double max_extra) {
  const size_t n = priority.size();
  auto count = [&](size_t i) { return 1 + uint64_t(std::min(max_extra, std::floor(double(priority[i]) * scale))); };
  // The total first, in 64 bits: 65 pieces of 66 million triangles wrapped a 32-bit sum (and
  // the references were written past what it allocated); 2^27 or more the builder refuses.
  uint64_t total = 0;
  for (size_t i = 0; i < n; ++i) total += count(i);
  check_primitive_count(total);
  std::vector<uint32_t> offset(n + 1, 0);
  for (size_t i = 0; i < n; ++i) offset[i + 1] = offset[i] + uint32_t(count(i));
  return offset;
}

PrimReferences presplit_triangles(std::span<const Triangle> tris, float budget, int max_pieces) {
  check_finite(tris);
  const size_t n = tris.size();
  if (!(budget > 0.0f) || n == 0) return one_reference_each(tris);
  const std::vector<float> priority = split_priorities(tris);
  struct Sum { double p = 0; Bounds3 scene; };
  // Deterministic reduction: the floating-point sum must not depend on the thread count.
  const Sum total = tbb::parallel_deterministic_reduce(
      tbb::blocked_range<size_t>(0, n, 4096), Sum{},
      [&](const auto& r, Sum s) {
        for (size_t i = r.begin(); i != r.end(); ++i) { s.p += priority[i]; s.scene.extend(tris[i].bounds()); }
        return s;
      },
      [](Sum a, const Sum& b) { a.p += b.p; a.scene.extend(b.scene); return a; });
  const double max_extra = double(std::clamp(max_pieces, 1, kBvhMaxPresplitPieces) - 1);
  const double scale = budget_scale(priority, total.p, double(budget) * double(n), max_extra);
  const std::vector<uint32_t> offset = reference_offsets(priority, scale, max_extra);
  PrimReferences refs;
  refs.boxes.resize(offset[n]);
  refs.ref_tri.resize(offset[n]);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      split_into(tris[i], tris[i].bounds(), offset[i + 1] - offset[i], total.scene, &refs.boxes[offset[i]]);
      for (uint32_t k = offset[i]; k < offset[i + 1]; ++k) refs.ref_tri[k] = uint32_t(i);
    }
  });
  return refs;
}

}  // namespace rayscout::detail
