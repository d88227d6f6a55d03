// Disjoint sets of 0 .. n-1 (union by assignment, path halving): groups nodes joined by
// branches into crossings (junctions.cpp) and a crossing's nodes into parts
// (bending.cpp).
#pragma once

#include <numeric>
#include <vector>

namespace mbest {

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void unite(int a, int b) { parent[find(a)] = find(b); }
};

}  // namespace mbest
