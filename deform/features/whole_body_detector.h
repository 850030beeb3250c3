// Whole-body self-intersection: which of a large triangle list (the whole skin, ~10^5
// triangles) cross each other — the broad phase that scales, for the `contact` feature
// (skin_contact.h). Same contract and same pairs as SelfIntersectionDetector::detect (the region
// detector), so either can stand for the other, and gpu::CollisionDetector reproduces both.
//
// WholeBodyDetector::detect
//   Inputs:  positions  #V posed vertex positions
//            indices    3 per mesh triangle; triangles sharing an index are mesh neighbours and
//                       never reported (pass seam-welded indices: CollisionRegions::welded_indices)
//            triangles  #T ids of the triangles to test against each other
//            threads    threads for the refit and the traversal (< 1: 1); the pairs do not
//                       depend on it
//   Output:  pairs      every {first < second} whose closed triangles meet (the exact test of
//                       triangle_intersection.h, after the same box and shared-vertex filters
//                       as the region detector), sorted, unique; cleared first.
// Broad phase: a bounding-volume hierarchy over the triangles' boxes. Its layout is built when
// the triangle list changes (another span than the last call's): the triangles in Morton order
// of their centroids (at that call's positions), 4 per leaf, an implicit complete binary tree
// over the leaves; every later call only refits the boxes bottom-up. Posing moves skin
// patches mostly rigidly, so the rest-time layout keeps tight boxes. Each leaf is tested
// against the leaves at or after it (each leaf pair once), blocks of leaves on `threads`
// threads (deform/simd/vertex_blocks.h). Buffers are kept between calls: once warm, starting
// the threads is the only allocation.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "deform/features/self_intersection.h"

namespace sweepd::deform {

class WholeBodyDetector {
 public:
  static constexpr std::uint32_t kLeafSize = 4;

  void detect(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
              std::span<const std::uint32_t> triangles, std::vector<TrianglePair>& pairs,
              int threads = 1);

 private:
  void build_layout(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                    std::span<const std::uint32_t> triangles);
  void refit(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
             int threads);
  // Pairs of leaf `leaf` against the leaves at or after it, appended to out.
  void query_leaf(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                  std::uint32_t leaf, std::vector<TrianglePair>& out) const;

  const std::uint32_t* built_triangles_ = nullptr;  // the list the layout was built for
  std::size_t built_size_ = 0;
  const std::uint32_t* built_indices_ = nullptr;
  std::vector<std::uint32_t> order_;  // triangle ids in leaf order (Morton)
  std::vector<TriangleBox> boxes_;    // per entry of order_
  std::vector<TriangleBox> nodes_;    // implicit tree: root 1, children 2n and 2n + 1
  std::uint32_t leaf_count_ = 0, leaf_base_ = 1, height_ = 0;  // leaves at [leaf_base_, 2 ×)
  std::vector<std::vector<TrianglePair>> found_;               // per thread block
};

}  // namespace sweepd::deform
