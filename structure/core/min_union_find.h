#pragma once
// Union-find whose root is always the smallest member, so a set's id is its first element (the
// same ids whatever order the unions come in).
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <vector>

namespace mspline::structure {

class MinUnionFind {
 public:
  using Index = std::uint32_t;
  explicit MinUnionFind(std::size_t n) : parent_(n) {
    std::iota(parent_.begin(), parent_.end(), Index{0});
  }
  Index find(Index x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  void unite(Index a, Index b) {
    a = find(a);
    b = find(b);
    if (a < b)
      parent_[b] = a;
    else if (b < a)
      parent_[a] = b;
  }

 private:
  std::vector<Index> parent_;
};

}  // namespace mspline::structure
