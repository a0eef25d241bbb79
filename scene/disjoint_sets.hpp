#pragma once
// Disjoint sets over indices 0..n-1 whose representative is always the set's lowest index (as a
// GPU union-find that hooks toward the minimum keeps it), with path halving. Shared by the
// volume's boundary pieces (renderer/volume/tet_adjacency) and FastAtlas's charts, where the
// lowest index names a chart.
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace prismoid {

struct DisjointSets {
  std::vector<uint32_t> parent;
  explicit DisjointSets(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  uint32_t find(uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  // Joins the sets of a and b; whether they were apart.
  bool unite(uint32_t a, uint32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    parent[std::max(a, b)] = std::min(a, b);
    return true;
  }
};

}  // namespace prismoid
