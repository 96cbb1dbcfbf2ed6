// Bvh2 single-ray traversal: ordered closest hit and early-exit any hit.
#include "rayscout/bvh/bvh2.h"

#include <algorithm>
#include <bit>

#include "rayscout/bvh/cull_interval.h"
#include "traversal_stack.h"
#include "box_test.h"

namespace rayscout {
namespace {

struct Entry {
  uint32_t node;
  float dist;  // entry distance of the node's box
};

// Pushes the hit children of an inner node (left = first, right = first + 1), the nearer one
// last so that it is popped first; entry(child, dist) makes the stack entry.
template <class Stack, class MakeEntry>
void push_hit_children(Stack& stack, uint32_t first, bool hl, bool hr, float dl, float dr, MakeEntry entry) {
  if (hl && hr) {
    if (dr < dl) {
      stack.push(entry(first, dl));
      stack.push(entry(first + 1, dr));
    } else {
      stack.push(entry(first + 1, dr));
      stack.push(entry(first, dl));
    }
  } else if (hl) {
    stack.push(entry(first, dl));
  } else if (hr) {
    stack.push(entry(first + 1, dr));
  }
}

// Calls visit(node, entry distance) for every start entry whose box the ray enters within
// [tmin, tmax()], in list order, until visit returns false; returns the box tests made. A
// candidate list is tested a group of entries at a time (intersect_nodes, identical to the
// scalar test), tmax() read before each group; a lone entry (the root) takes the scalar test.
template <class TMax, class Visit>
uint64_t visit_hit_starts(const Bvh2Node* nodes, std::span<const uint32_t> start, const Vec3& org, const Vec3& inv_dir,
                          float tmin, TMax tmax, Visit visit) {
  if (start.size() == 1) {
    float d;
    if (detail::intersect_box_robust(org, inv_dir, nodes[start[0]].bounds, tmin, tmax(), d)) visit(start[0], d);
    return 1;
  }
  uint64_t tests = 0;
  for (size_t b = 0; b < start.size(); b += detail::kNodeGroup) {
    const int n = int(std::min<size_t>(detail::kNodeGroup, start.size() - b));
    float dist[detail::kNodeGroup];
    tests += uint64_t(n);
    for (uint32_t mask = detail::intersect_nodes(nodes, &start[b], n, org, inv_dir, tmin, tmax(), dist); mask;
         mask &= mask - 1) {
      const int k = std::countr_zero(mask);
      if (!visit(start[b + k], dist[k])) return tests;
    }
  }
  return tests;
}

}  // namespace

template <bool CaptureStats>
Hit Bvh2::intersect(const Ray& ray, std::span<const uint32_t> start, TraceStats* stats) const {
  Hit best;
  if (nodes.empty()) return best;
  best.t = ray.tmax;
  const CullInterval cull = cull_interval(ray);
  const float box_tmin = cull.near(ray.tmin);
  float cull_t = cull.far(best.t);
  const RayPrecomp rp(ray.dir);
  const uint32_t root = 0;
  if (start.empty()) start = std::span<const uint32_t>(&root, 1);
  detail::TraversalStack<Entry> stack(size_t(depth_) + 2);
  uint64_t steps = 0, box_tests = 0, tri_tests = 0;
  // Each hit start entry is traversed once the stack is empty (exactly where it would pop had
  // all been pushed up front), so an entry beyond the current hit is skipped at its pop.
  box_tests += visit_hit_starts(nodes.data(), start, ray.org, rp.inv_dir, box_tmin, [&] { return cull_t; },
                                [&](uint32_t s, float d) {
    stack.push({s, d});
    while (!stack.empty()) {
      const Entry e = stack.pop();
      // Closed, like the box test. A box entered at the best t (it may hold an equal-t hit
      // with a smaller id) passes either way: cull_t lies CullInterval::far's slack beyond it.
      if (e.dist > cull_t) continue;
      ++steps;
      const Bvh2Node& n = nodes[e.node];
      if (n.is_leaf()) {
        for (uint32_t k = n.first; k < n.first + n.count; ++k) {
          float t, u, v;
          ++tri_tests;
          if (intersect_triangle(ray.org, rp, leaf_tris[k], ray.tmin, best.t, t, u, v) &&
              is_closer(t, prim_ids[k], best.t, best.prim)) {
            best = {t, prim_ids[k], u, v};
            cull_t = cull.far(t);
          }
        }
        continue;
      }
      float dl, dr;
      const bool hl = detail::intersect_box_robust(ray.org, rp.inv_dir, nodes[n.first].bounds, box_tmin, cull_t, dl);
      const bool hr = detail::intersect_box_robust(ray.org, rp.inv_dir, nodes[n.first + 1].bounds, box_tmin, cull_t, dr);
      box_tests += 2;
      push_hit_children(stack, n.first, hl, hr, dl, dr, [](uint32_t c, float d) { return Entry{c, d}; });
    }
    return true;
  });
  if constexpr (CaptureStats) {
    stats->traversal_steps += steps;
    stats->ray_box_tests += box_tests;
    stats->ray_tri_tests += tri_tests;
  }
  if (!best.hit()) best = Hit{};
  return best;
}

template <bool CaptureStats>
bool Bvh2::occluded(const Ray& ray, std::span<const uint32_t> start, TraceStats* stats) const {
  if (nodes.empty()) return false;
  const RayPrecomp rp(ray.dir);
  const CullInterval cull = cull_interval(ray);
  const float box_tmin = cull.near(ray.tmin), box_tmax = cull.far(ray.tmax);
  const uint32_t root = 0;
  if (start.empty()) start = std::span<const uint32_t>(&root, 1);
  detail::TraversalStack<uint32_t> stack(size_t(depth_) + 2);
  uint64_t steps = 0, box_tests = 0, tri_tests = 0;
  bool hit = false;
  // An early hit skips the later start entries (see intersect).
  box_tests += visit_hit_starts(nodes.data(), start, ray.org, rp.inv_dir, box_tmin, [&] { return box_tmax; },
                                [&](uint32_t s, float) {
    stack.push(s);
    while (!stack.empty() && !hit) {
      ++steps;
      const Bvh2Node& n = nodes[stack.pop()];
      if (n.is_leaf()) {
        for (uint32_t k = n.first; k < n.first + n.count; ++k) {
          float t, u, v;
          ++tri_tests;
          if (intersect_triangle(ray.org, rp, leaf_tris[k], ray.tmin, ray.tmax, t, u, v)) {
            hit = true;
            break;
          }
        }
        continue;
      }
      float dl, dr;
      const bool hl = detail::intersect_box_robust(ray.org, rp.inv_dir, nodes[n.first].bounds, box_tmin, box_tmax, dl);
      const bool hr = detail::intersect_box_robust(ray.org, rp.inv_dir, nodes[n.first + 1].bounds, box_tmin, box_tmax, dr);
      box_tests += 2;
      // Near child on top: an early hit ends the ray sooner.
      push_hit_children(stack, n.first, hl, hr, dl, dr, [](uint32_t c, float) { return c; });
    }
    return !hit;
  });
  if constexpr (CaptureStats) {
    stats->traversal_steps += steps;
    stats->ray_box_tests += box_tests;
    stats->ray_tri_tests += tri_tests;
  }
  return hit;
}

template Hit Bvh2::intersect<false>(const Ray&, std::span<const uint32_t>, TraceStats*) const;
template Hit Bvh2::intersect<true>(const Ray&, std::span<const uint32_t>, TraceStats*) const;
template bool Bvh2::occluded<false>(const Ray&, std::span<const uint32_t>, TraceStats*) const;
template bool Bvh2::occluded<true>(const Ray&, std::span<const uint32_t>, TraceStats*) const;

}  // namespace rayscout
