// TreeView: flattening Bvh2 and WideBvh.
#include "rayscout/shafts/tree_view.h"

namespace rayscout {

TreeView TreeView::from_bvh2(const Bvh2& bvh, int levels) {
  TreeView t;
  t.arity = 2;
  t.split_order = levels <= 1;
  const size_t n = bvh.nodes.size();
  t.bounds.resize(n);
  t.ref.resize(n);
  t.split_axis.resize(n);
  t.child_begin.resize(n + 1);
  t.child.reserve(n);
  std::vector<uint32_t> frontier, next;
  for (size_t i = 0; i < n; ++i) {
    const Bvh2Node& node = bvh.nodes[i];
    t.bounds[i] = node.bounds;
    t.ref[i] = uint32_t(i);
    t.split_axis[i] = t.split_order ? int8_t(node.axis) : int8_t(-1);
    t.child_begin[i] = uint32_t(t.child.size());
    if (node.is_leaf()) continue;
    frontier.assign({node.first, node.first + 1});
    for (int l = 1; l < levels; ++l) {
      next.clear();
      for (uint32_t c : frontier) {
        const Bvh2Node& cn = bvh.nodes[c];
        if (cn.is_leaf()) next.push_back(c);
        else next.insert(next.end(), {cn.first, cn.first + 1});
      }
      frontier.swap(next);
    }
    t.child.insert(t.child.end(), frontier.begin(), frontier.end());
  }
  t.child_begin[n] = uint32_t(t.child.size());
  return t;
}

TreeView TreeView::from_wide(const WideBvh& bvh) {
  TreeView t;
  t.arity = kWideWidth;
  t.split_order = false;
  const size_t n = bvh.nodes.size();
  if (n == 0) {
    t.child_begin.push_back(0);
    return t;
  }
  t.bounds.resize(n);
  t.ref.resize(n);
  t.bounds[0] = bvh.bounds;
  for (size_t i = 0; i < n; ++i) t.ref[i] = uint32_t(i);
  // Children lists of wide nodes; leaves get indices after the nodes.
  std::vector<std::vector<uint32_t>> kids(n);
  for (size_t i = 0; i < n; ++i) {
    const WideNode& node = bvh.nodes[i];
    for (uint32_t s = 0; s < node.count; ++s) {
      const uint32_t r = node.child[s];
      uint32_t idx;
      if (WideRef::is_leaf(r)) {
        idx = uint32_t(t.bounds.size());
        t.bounds.push_back(node.child_bounds(int(s)));
        t.ref.push_back(r);
      } else {
        idx = r;
        t.bounds[r] = node.child_bounds(int(s));
      }
      kids[i].push_back(idx);
    }
  }
  const size_t total = t.bounds.size();
  t.split_axis.assign(total, -1);
  t.child_begin.resize(total + 1);
  for (size_t i = 0; i < total; ++i) {
    t.child_begin[i] = uint32_t(t.child.size());
    if (i < n) t.child.insert(t.child.end(), kids[i].begin(), kids[i].end());
  }
  t.child_begin[total] = uint32_t(t.child.size());
  return t;
}

}  // namespace rayscout
