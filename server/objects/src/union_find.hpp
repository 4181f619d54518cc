#pragma once
// Internal: disjoint sets over 0..n-1 with path halving and union by size.
#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

namespace semfuse::objects::detail {

class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n), size_(n, 1) { std::iota(parent_.begin(), parent_.end(), 0); }

  int32_t find(int32_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  // True when a and b were in different sets.
  bool unite(int32_t a, int32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    if (size_[a] < size_[b]) std::swap(a, b);
    parent_[b] = a;
    size_[a] += size_[b];
    return true;
  }
  // Makes root `child` part of root `parent`'s set, keeping `parent` the root.
  void attach(int32_t child, int32_t parent) {
    parent_[child] = parent;
    size_[parent] += size_[child];
  }
  std::size_t size() const { return parent_.size(); }

  // Dense ids 0..count-1 of the sets, in order of their first member; returns count.
  int32_t compact(std::vector<int32_t>& id_of) {
    id_of.assign(parent_.size(), -1);
    std::vector<int32_t> root_id(parent_.size(), -1);
    int32_t count = 0;
    for (std::size_t i = 0; i < parent_.size(); ++i) {
      const int32_t root = find(static_cast<int32_t>(i));
      if (root_id[root] < 0) root_id[root] = count++;
      id_of[i] = root_id[root];
    }
    return count;
  }

 private:
  std::vector<int32_t> parent_;
  std::vector<int32_t> size_;
};

}  // namespace semfuse::objects::detail
