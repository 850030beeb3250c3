// Disjoint sets (union-find) over 0..n-1, and the connected pieces of a triangle mesh.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <span>
#include <vector>

namespace sweepd::deform {

// Path halving; the smaller id becomes the root, so a set's root is its smallest member.
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) {
    std::iota(parent_.begin(), parent_.end(), std::uint32_t{0});
  }
  std::uint32_t find(std::uint32_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void join(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<std::uint32_t> parent_;
};

// Per vertex (vertex_count entries), the smallest vertex id of its piece: triangles
// (`indices`, three per triangle, each < vertex_count) connect the vertices they share.
inline std::vector<std::uint32_t> vertex_components(std::span<const std::uint32_t> indices,
                                                    std::size_t vertex_count) {
  DisjointSets sets(vertex_count);
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
    sets.join(indices[t], indices[t + 1]);
    sets.join(indices[t], indices[t + 2]);
  }
  std::vector<std::uint32_t> component(vertex_count);
  for (std::uint32_t v = 0; v < vertex_count; ++v) component[v] = sets.find(v);
  return component;
}

}  // namespace sweepd::deform
