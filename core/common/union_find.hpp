// SPDX-License-Identifier: MIT
// Disjoint sets over 0..n-1 (union-find with path halving): pieces of a mesh, clumps of particles.
#pragma once

#include <numeric>
#include <vector>

namespace fesph {

class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }

  /// The representative of a's set.
  int find(int a) {
    while (parent_[a] != a) a = parent_[a] = parent_[parent_[a]];
    return a;
  }

  /// find's answer without shortening the path on the way: threads may ask side by side.
  int root(int a) const {
    while (parent_[a] != a) a = parent_[a];
    return a;
  }

  /// Merges a's set into b's (b's representative stays the representative).
  void join(int a, int b) { parent_[find(a)] = find(b); }

 private:
  std::vector<int> parent_;
};

}  // namespace fesph
