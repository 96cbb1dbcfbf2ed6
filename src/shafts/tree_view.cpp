// TreeView: flattening Bvh2 and WideBvh.
#include "rayscout/shafts/tree_view.h"

namespace rayscout {

TreeView TreeView::from_bvh2(const Bvh2& bvh) {
  TreeView t;
  t.arity = 2;
  const size_t n = bvh.nodes.size();
  t.bounds.resize(n);
  t.ref.resize(n);
  t.split_axis.resize(n);
  t.child_begin.resize(n + 1);
  t.child.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    const Bvh2Node& node = bvh.nodes[i];
    t.bounds[i] = node.bounds;
    t.ref[i] = uint32_t(i);
    t.split_axis[i] = int8_t(node.axis);
    t.child_begin[i] = uint32_t(t.child.size());
    if (!node.is_leaf()) {
      t.child.push_back(node.first);
      t.child.push_back(node.first + 1);
    }
  }
  t.child_begin[n] = uint32_t(t.child.size());
  return t;
}

TreeView TreeView::from_wide(const WideBvh& bvh) {
  TreeView t;
  t.arity = kWideWidth;
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
