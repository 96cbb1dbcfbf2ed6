// TraversalStack (private): a traversal stack on the call stack, on the heap only when deep.
#pragma once

#include <cstddef>
#include <vector>

namespace rayscout::detail {

/// Stack of traversal entries with room for `capacity` items; no bounds checks while pushing.
template <class Entry, size_t kLocal = 256>
class TraversalStack {
 public:
  explicit TraversalStack(size_t capacity) {
    if (capacity > kLocal) {
      heap_.resize(capacity);
      data_ = heap_.data();
    }
  }
  void push(const Entry& e) { data_[size_++] = e; }
  /// The first free slot: the base of a traversal that keeps its own stack pointer.
  Entry* top() { return data_ + size_; }
  Entry pop() { return data_[--size_]; }
  bool empty() const { return size_ == 0; }

 private:
  Entry local_[kLocal];
  std::vector<Entry> heap_;
  Entry* data_ = local_;
  size_t size_ = 0;
};

}  // namespace rayscout::detail
