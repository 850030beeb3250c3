#include "deform/features/whole_body_detector.h"

#include <algorithm>
#include <cmath>

#include "deform/simd/vertex_blocks.h"

namespace sweepd::deform {
namespace {

// 10 bits of x, y, z interleaved.
std::uint32_t spread_bits(std::uint32_t v) {
  v = (v | (v << 16)) & 0x030000FFu;
  v = (v | (v << 8)) & 0x0300F00Fu;
  v = (v | (v << 4)) & 0x030C30C3u;
  v = (v | (v << 2)) & 0x09249249u;
  return v;
}

constexpr TriangleBox kEmptyBox{glm::vec3(INFINITY), glm::vec3(-INFINITY)};

TriangleBox merged(const TriangleBox& a, const TriangleBox& b) {
  return {glm::min(a.lo, b.lo), glm::max(a.hi, b.hi)};
}

}  // namespace

void WholeBodyDetector::build_layout(std::span<const glm::vec3> positions,
                                     std::span<const std::uint32_t> indices,
                                     std::span<const std::uint32_t> triangles) {
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (std::uint32_t t : triangles) {
    const TriangleBox box = triangle_box(positions, indices, t);
    lo = glm::min(lo, box.lo);
    hi = glm::max(hi, box.hi);
  }
  const glm::vec3 scale = 1023.0f / glm::max(hi - lo, glm::vec3(1e-30f));
  std::vector<std::pair<std::uint32_t, std::uint32_t>> keyed(triangles.size());
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const TriangleBox box = triangle_box(positions, indices, triangles[i]);
    glm::vec3 c = ((box.lo + box.hi) * 0.5f - lo) * scale;
    if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z)) c = glm::vec3(0.0f);
    const glm::uvec3 cell(glm::clamp(c, glm::vec3(0.0f), glm::vec3(1023.0f)));
    keyed[i] = {(spread_bits(cell.x) << 2) | (spread_bits(cell.y) << 1) | spread_bits(cell.z),
                triangles[i]};
  }
  std::sort(keyed.begin(), keyed.end());
  order_.resize(triangles.size());
  for (std::size_t i = 0; i < keyed.size(); ++i) order_[i] = keyed[i].second;
  leaf_count_ = static_cast<std::uint32_t>((triangles.size() + kLeafSize - 1) / kLeafSize);
  leaf_base_ = 1;
  height_ = 0;
  while (leaf_base_ < leaf_count_) leaf_base_ *= 2, ++height_;
  nodes_.assign(2 * leaf_base_, kEmptyBox);
  boxes_.resize(triangles.size());
  built_triangles_ = triangles.data();
  built_size_ = triangles.size();
  built_indices_ = indices.data();
}

void WholeBodyDetector::refit(std::span<const glm::vec3> positions,
                              std::span<const std::uint32_t> indices, int threads) {
  run_in_vertex_blocks(leaf_count_, threads, [&](std::size_t begin, std::size_t end) {
    for (std::size_t leaf = begin; leaf < end; ++leaf) {
      TriangleBox box = kEmptyBox;
      const std::size_t last = std::min<std::size_t>((leaf + 1) * kLeafSize, order_.size());
      for (std::size_t i = leaf * kLeafSize; i < last; ++i) {
        boxes_[i] = triangle_box(positions, indices, order_[i]);
        box = merged(box, boxes_[i]);
      }
      nodes_[leaf_base_ + leaf] = box;
    }
  });
  for (std::uint32_t n = leaf_base_ - 1; n >= 1; --n)
    nodes_[n] = merged(nodes_[2 * n], nodes_[2 * n + 1]);
}

void WholeBodyDetector::query_leaf(std::span<const glm::vec3> positions,
                                   std::span<const std::uint32_t> indices, std::uint32_t leaf,
                                   std::vector<TrianglePair>& out) const {
  const TriangleBox& own = nodes_[leaf_base_ + leaf];
  const std::size_t own_begin = static_cast<std::size_t>(leaf) * kLeafSize;
  const std::size_t own_end = std::min<std::size_t>(own_begin + kLeafSize, order_.size());
  // (node, height above the leaves); the tree is at most 32 levels deep.
  std::pair<std::uint32_t, std::uint32_t> stack[64];
  int top = 0;
  stack[top++] = {1u, height_};
  while (top > 0) {
    const auto [node, height] = stack[--top];
    // Leaves under the node: [first, first + 2^height); only those at or after `leaf`.
    const std::uint64_t first = (static_cast<std::uint64_t>(node) << height) - leaf_base_;
    if (first + (std::uint64_t{1} << height) <= leaf) continue;
    if (!boxes_overlap(own, nodes_[node])) continue;
    if (height > 0) {
      stack[top++] = {2 * node, height - 1};
      stack[top++] = {2 * node + 1, height - 1};
      continue;
    }
    const std::size_t other_begin = static_cast<std::size_t>(first) * kLeafSize;
    const std::size_t other_end = std::min<std::size_t>(other_begin + kLeafSize, order_.size());
    for (std::size_t i = own_begin; i < own_end; ++i) {
      if (!boxes_overlap(boxes_[i], nodes_[node])) continue;
      for (std::size_t j = std::max(other_begin, i + 1); j < other_end; ++j) {
        if (!boxes_overlap(boxes_[i], boxes_[j])) continue;
        std::uint32_t s = order_[i], t = order_[j];
        if (s > t) std::swap(s, t);
        if (s == t || share_a_vertex(indices, s, t)) continue;
        if (mesh_triangles_intersect(positions, indices, s, t)) out.push_back({s, t});
      }
    }
  }
}

void WholeBodyDetector::detect(std::span<const glm::vec3> positions,
                               std::span<const std::uint32_t> indices,
                               std::span<const std::uint32_t> triangles,
                               std::vector<TrianglePair>& pairs, int threads) {
  pairs.clear();
  if (triangles.size() < 2) return;
  if (triangles.data() != built_triangles_ || triangles.size() != built_size_ ||
      indices.data() != built_indices_)
    build_layout(positions, indices, triangles);
  refit(positions, indices, threads);
  const std::size_t blocks =
      std::clamp<std::size_t>(static_cast<std::size_t>(std::max(threads, 1)), 1, leaf_count_);
  found_.resize(std::max(found_.size(), blocks));
  // Contiguous blocks of leaves, one per thread; each block's pairs in its own buffer.
  run_in_vertex_blocks(blocks, static_cast<int>(blocks), [&](std::size_t begin, std::size_t end) {
    for (std::size_t b = begin; b < end; ++b) {
      std::vector<TrianglePair>& out = found_[b];
      out.clear();
      const std::uint32_t first = static_cast<std::uint32_t>(leaf_count_ * b / blocks);
      const std::uint32_t last = static_cast<std::uint32_t>(leaf_count_ * (b + 1) / blocks);
      for (std::uint32_t leaf = first; leaf < last; ++leaf)
        query_leaf(positions, indices, leaf, out);
    }
  });
  for (std::size_t b = 0; b < blocks; ++b)
    pairs.insert(pairs.end(), found_[b].begin(), found_[b].end());
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
}

}  // namespace sweepd::deform
