#pragma once
// Leaf origin -> position in a list of leaves, for code that moves between neighbouring leaves
// many times (a ray every few cells, the mesher 27 times per leaf): open addressing with linear
// probing, at most half full. OpenVDB's accessor would walk the
// tree for each new leaf, and std::unordered_map<Coord> hashes and chases a node per lookup.
// Internal.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <openvdb/openvdb.h>

namespace semfuse::render::detail {

class LeafIndex {
 public:
  static constexpr uint32_t kNone = UINT32_MAX;

  LeafIndex() = default;
  // origin_of(i), i < count: the origin of leaf i (a multiple of 8 on each axis, all distinct).
  template <class OriginOf>
  LeafIndex(std::size_t count, OriginOf origin_of) {
    std::size_t slots = 16;
    while (slots < 2 * count) slots *= 2;
    slot_mask_ = slots - 1;
    hash_shift_ = 64 - __builtin_ctzll(slots);
    keys_.assign(slots, openvdb::Coord());
    slots_.assign(slots, kNone);
    for (std::size_t i = 0; i < count; ++i) {
      const openvdb::Coord origin = origin_of(i);
      std::size_t slot = hashSlot(origin);
      while (slots_[slot] != kNone) slot = (slot + 1) & slot_mask_;
      keys_[slot] = origin;
      slots_[slot] = static_cast<uint32_t>(i);
    }
  }

  // The position of the leaf at `origin`, or kNone.
  uint32_t find(const openvdb::Coord& origin) const {
    if (slots_.empty()) return kNone;
    for (std::size_t slot = hashSlot(origin);; slot = (slot + 1) & slot_mask_) {
      const uint32_t index = slots_[slot];
      if (index == kNone || keys_[slot] == origin) return index;
    }
  }

 private:
  // Leaf origins are multiples of 8: 21 bits per axis of origin / 8 mixed into one word (the
  // keys themselves are compared whole, so origins that share these bits only share a probe run).
  std::size_t hashSlot(const openvdb::Coord& o) const {
    auto axis = [](int32_t v) { return static_cast<uint64_t>(static_cast<uint32_t>(v >> 3) & 0x1FFFFFu); };
    const uint64_t packed = axis(o.x()) | (axis(o.y()) << 21) | (axis(o.z()) << 42);
    return static_cast<std::size_t>((packed * 0x9E3779B97F4A7C15ull) >> hash_shift_);
  }

  std::vector<openvdb::Coord> keys_;
  std::vector<uint32_t> slots_;  // position of the leaf, kNone where free
  std::size_t slot_mask_ = 0;
  int hash_shift_ = 64;
};

}  // namespace semfuse::render::detail
