// Bvh2 single-ray traversal: ordered closest hit and early-exit any hit.
#include "rayscout/bvh/bvh2.h"
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

}  // namespace

template <bool CaptureStats>
Hit Bvh2::intersect(const Ray& ray, std::span<const Triangle> tris, std::span<const uint32_t> start,
                    TraceStats* stats) const {
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
  // Start entries are box tested lazily, the next one only once the stack is empty (exactly
  // where it would pop had all been pushed up front): entries beyond the hit are never tested.
  for (const uint32_t s : start) {
    float d;
    ++box_tests;
    if (!detail::intersect_box_robust(ray.org, rp.inv_dir, nodes[s].bounds, box_tmin, cull_t, d)) continue;
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
          const uint32_t p = prim_ids[k];
          float t, u, v;
          ++tri_tests;
          if (intersect_triangle(ray.org, rp, tris[p], ray.tmin, best.t, t, u, v) &&
              is_closer(t, p, best.t, best.prim)) {
            best = {t, p, u, v};
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
  }
  if constexpr (CaptureStats) {
    stats->traversal_steps += steps;
    stats->ray_box_tests += box_tests;
    stats->ray_tri_tests += tri_tests;
  }
  if (!best.hit()) best = Hit{};
  return best;
}

template <bool CaptureStats>
bool Bvh2::occluded(const Ray& ray, std::span<const Triangle> tris, std::span<const uint32_t> start,
                    TraceStats* stats) const {
  if (nodes.empty()) return false;
  const RayPrecomp rp(ray.dir);
  const CullInterval cull = cull_interval(ray);
  const float box_tmin = cull.near(ray.tmin), box_tmax = cull.far(ray.tmax);
  const uint32_t root = 0;
  if (start.empty()) start = std::span<const uint32_t>(&root, 1);
  detail::TraversalStack<uint32_t> stack(size_t(depth_) + 2);
  uint64_t steps = 0, box_tests = 0, tri_tests = 0;
  bool hit = false;
  // Start entries are box tested lazily (see intersect): an early hit skips the later ones.
  for (size_t k = 0; k < start.size() && !hit; ++k) {
    float d;
    ++box_tests;
    if (!detail::intersect_box_robust(ray.org, rp.inv_dir, nodes[start[k]].bounds, box_tmin, box_tmax, d)) continue;
    stack.push(start[k]);
    while (!stack.empty() && !hit) {
      ++steps;
      const Bvh2Node& n = nodes[stack.pop()];
      if (n.is_leaf()) {
        for (uint32_t k = n.first; k < n.first + n.count; ++k) {
          float t, u, v;
          ++tri_tests;
          if (intersect_triangle(ray.org, rp, tris[prim_ids[k]], ray.tmin, ray.tmax, t, u, v)) {
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
  }
  if constexpr (CaptureStats) {
    stats->traversal_steps += steps;
    stats->ray_box_tests += box_tests;
    stats->ray_tri_tests += tri_tests;
  }
  return hit;
}

template Hit Bvh2::intersect<false>(const Ray&, std::span<const Triangle>, std::span<const uint32_t>, TraceStats*) const;
template Hit Bvh2::intersect<true>(const Ray&, std::span<const Triangle>, std::span<const uint32_t>, TraceStats*) const;
template bool Bvh2::occluded<false>(const Ray&, std::span<const Triangle>, std::span<const uint32_t>, TraceStats*) const;
template bool Bvh2::occluded<true>(const Ray&, std::span<const Triangle>, std::span<const uint32_t>, TraceStats*) const;

}  // namespace rayscout
