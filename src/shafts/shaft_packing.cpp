// ShaftCollection::pack: the lists of the listed voxels into the lookup tables and one list
// area, identical lists stored once (paper sec. 4.4), entry boxes after their lists.
#include "rayscout/shafts/shaft_collection.h"

#include <algorithm>
#include <cstring>
#include <optional>

#include "entry_box_codec.h"
#include "rayscout/core/input_error.h"
#include "voxel_lists.h"

namespace rayscout {

namespace {

/// FNV-1a, a 32-bit word at a time, over a list's node references (tree.ref), seeded with its
/// length.
uint32_t hash_list(const TreeView& tree, const uint32_t* nodes, uint32_t len) {
  uint64_t h = 1469598103934665603ull ^ len;
  for (uint32_t i = 0; i < len; ++i) h = (h ^ tree.ref[nodes[i]]) * 1099511628211ull;
  return uint32_t(h ^ (h >> 32));
}

/// Identical lists are stored once (paper sec. 4.4): open addressing over the lists' contents,
/// at load <= 1/2. A slot holds a list's hash and its packed entry (offset << 5 | length) plus
/// 1, 0 = free, side by side: one cache miss per probe. The lists come in packing order, whose
/// hashes are known up front, so the probe of the list kAhead lists later is prefetched (the
/// probes are random accesses into a table of several MiB).
class ListDedup {
 public:
  /// hashes: hash_list of every list in packing order.
  explicit ListDedup(std::vector<uint32_t> hashes) : hashes_(std::move(hashes)) {
    size_t capacity = 1024;
    while (capacity < 2 * hashes_.size()) capacity *= 2;
    slots_.resize(capacity);
    mask_ = capacity - 1;
  }
  /// The offset of an earlier list equal to the next list in packing order, area[offset,
  /// offset + len); else remembers that one and returns nothing.
  std::optional<uint32_t> find_or_add_next(const std::vector<uint32_t>& area, uint32_t offset, uint32_t len) {
    if (next_ + kAhead < hashes_.size()) __builtin_prefetch(&slots_[hashes_[next_ + kAhead] & mask_]);
    const uint32_t hash = hashes_[next_++];
    size_t slot = hash & mask_;
    for (; slots_[slot].list != 0; slot = (slot + 1) & mask_) {
      if (slots_[slot].hash != hash) continue;
      const uint32_t packed = slots_[slot].list - 1, o = packed >> 5;
      if ((packed & 31u) == len && std::equal(area.begin() + o, area.begin() + o + len, area.begin() + offset))
        return o;
    }
    slots_[slot] = {hash, ((offset << 5) | len) + 1};
    return std::nullopt;
  }

 private:
  static constexpr size_t kAhead = 8;
  struct Slot {
    uint32_t hash = 0, list = 0;
  };
  std::vector<uint32_t> hashes_;
  size_t next_ = 0;
  std::vector<Slot> slots_;
  size_t mask_ = 0;
};

/// The hashes of every list of `lists`, in packing order (listed voxel, then cell).
std::vector<uint32_t> hashes_in_packing_order(const TreeView& tree, const std::vector<detail::VoxelLists>& lists) {
  std::vector<uint32_t> hashes;
  for (const detail::VoxelLists& vl : lists)
    for (uint32_t cell = 0; cell < vl.status.size(); ++cell)
      if (vl.status[cell] == detail::VoxelLists::kList)
        hashes.push_back(hash_list(tree, vl.data.data() + vl.begin[cell], vl.len[cell]));
  return hashes;
}

/// The quantised boxes of tree nodes, each encoded once, on first use; none without a codec.
class EntryBoxes {
 public:
  EntryBoxes(const TreeView& tree, const detail::EntryBoxCodec* codec)
      : tree_(tree), codec_(codec), boxes_(codec ? tree.size() : 0), encoded_(boxes_.size(), 0) {}
  bool stored() const { return codec_ != nullptr; }
  const detail::QBox& of(uint32_t node) {
    if (!encoded_[node]) {
      boxes_[node] = codec_->encode(tree_.bounds[node]);
      encoded_[node] = 1;
    }
    return boxes_[node];
  }

 private:
  const TreeView& tree_;
  const detail::EntryBoxCodec* codec_;
  std::vector<detail::QBox> boxes_;
  std::vector<uint8_t> encoded_;
};

/// Fills the list area (ShaftCollection::lists_): per unique list its node references, then
/// (with an entry-box codec) its entry-box rows, 6 len bytes padded to a word.
class ListAreaWriter {
 public:
  ListAreaWriter(const TreeView& tree, const detail::EntryBoxCodec* codec, bool dedup,
                 const std::vector<detail::VoxelLists>& lists, std::vector<uint32_t>& area)
      : tree_(tree),
        area_(area),
        dedup_(dedup),
        twins_(dedup ? hashes_in_packing_order(tree, lists) : std::vector<uint32_t>{}),
        boxes_(tree, codec) {
    size_t total_entries = 0;
    for (const detail::VoxelLists& vl : lists) total_entries += vl.data.size();
    area_.clear();
    area_.reserve(total_entries * (codec ? 3 : 1) + 2);
  }

  /// Where the list nodes[0, len) starts in the area (its packed entry's offset): an equal
  /// earlier list's start, or the end of the area, where it is appended. Call in packing order.
  uint32_t add(const uint32_t* nodes, uint32_t len) {
    // Append the list, then take it back if an equal one is stored already.
    const uint32_t offset = uint32_t(area_.size());
    for (uint32_t k = 0; k < len; ++k) area_.push_back(tree_.ref[nodes[k]]);
    if (dedup_)
      if (const std::optional<uint32_t> twin = twins_.find_or_add_next(area_, offset, len)) {
        area_.resize(offset);
        saved_bytes_ += words(len) * sizeof(uint32_t);
        return *twin;
      }
    if (offset >= (1u << 27)) throw InputError("shafts: list area exceeds 2^27 entries; lower the resolution");
    ++unique_;
    if (boxes_.stored()) append_rows(nodes, len, offset);
    return offset;
  }
  /// Ends the area: the padding the SIMD rows read past the last list.
  void finish() {
    if (boxes_.stored()) area_.resize(area_.size() + 2, 0);  // SIMD rows read 8 bytes
    area_.shrink_to_fit();
  }
  size_t unique_lists() const { return unique_; }
  size_t saved_bytes() const { return saved_bytes_; }

 private:
  /// 4-byte words a stored list of len entries takes: its ids, then its rows padded to a word.
  size_t words(uint32_t len) const { return len + (boxes_.stored() ? (6 * size_t(len) + 3) / 4 : 0); }

  /// The list's entry-box rows (layout: Candidates::boxes), after its ids: one cache line
  /// serves both.
  void append_rows(const uint32_t* nodes, uint32_t len, uint32_t offset) {
    uint8_t rows[6 * 31];
    for (uint32_t k = 0; k < len; ++k) {
      const detail::QBox& q = boxes_.of(nodes[k]);
      for (int row = 0; row < 3; ++row) {
        rows[size_t(row) * len + k] = q.lo[row];
        rows[size_t(row + 3) * len + k] = q.hi[row];
      }
    }
    const size_t at_rows = area_.size();
    area_.resize(offset + words(len), 0);
    std::memcpy(area_.data() + at_rows, rows, 6 * size_t(len));
  }

  const TreeView& tree_;
  std::vector<uint32_t>& area_;
  bool dedup_;
  ListDedup twins_;  ///< empty without dedup
  EntryBoxes boxes_;
  size_t unique_ = 0, saved_bytes_ = 0;
};

}  // namespace

void ShaftCollection::pack(const TreeView& tree, const std::vector<uint32_t>& listed,
                           const std::vector<detail::VoxelLists>& lists, bool dedup) {
  const uint32_t cells = grid_.cells_per_voxel();
  ShaftStats& st = stats_;
  st.res = grid_.res();
  st.dir_res = grid_.dir_res();
  st.voxels = grid_.voxel_count();
  st.shafts = st.voxels * cells;
  st.listed_voxels = listed.size();
  st.length_histogram.assign(32, 0);
  voxel_base_.assign(st.voxels, kNoVoxel);
  entries_.assign(listed.size() * cells, 0);
  ListAreaWriter area(tree, entry_codec_.get(), dedup, lists, lists_);
  size_t total_len = 0, nonempty = 0;
  for (size_t li = 0; li < listed.size(); ++li) {
    const detail::VoxelLists& vl = lists[li];
    const uint32_t base = uint32_t(li * cells);
    voxel_base_[listed[li]] = base;
    st.near_retries += vl.near_retries;
    st.overflow_retries += vl.retries;
    st.overflow_fallbacks += vl.fallbacks;
    for (uint32_t cell = 0; cell < cells; ++cell) {
      if (vl.status[cell] == detail::VoxelLists::kNoList) continue;
      ++st.listed_shafts;
      if (vl.status[cell] == detail::VoxelLists::kReachesNothing) {
        ++st.empty_lists;
        entries_[base + cell] = kEmptyList;
        continue;
      }
      const uint32_t len = vl.len[cell];
      entries_[base + cell] = (area.add(vl.data.data() + vl.begin[cell], len) << 5) | len;
      ++st.length_histogram[len];
      total_len += len;
      ++nonempty;
      st.max_list = std::max(st.max_list, int(len));
    }
  }
  area.finish();
  st.unique_lists = area.unique_lists();
  st.dedup_saved_bytes = area.saved_bytes();
  st.mean_list = nonempty ? double(total_len) / double(nonempty) : 0.0;
  st.lookup_bytes = (voxel_base_.size() + entries_.size()) * sizeof(uint32_t);
  st.list_bytes = lists_.size() * sizeof(uint32_t);  // ids (and entry-box rows)
}

}  // namespace rayscout
