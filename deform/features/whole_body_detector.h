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
// patches mostly rigidly, so the rest-time layout keeps tight boxes. The tree is tested against
// itself top-down (self(n) = self(left) + self(right) + cross(left, right), cross testing its
// four child pairs at once and descending into those that overlap), so each pair of
// overlapping leaves is reached once with no per-leaf query from the root. A leaf pair tests one triangle against the other leaf's four
// in SIMD lanes: the four box tests and the nine welded-vertex comparisons that drop mesh
// neighbours (most overlapping boxes on a skin are neighbours') at once, before the exact test.
// The top of the descent is cut into tasks taken by `threads` threads as they finish.
// Buffers are kept between calls: once warm, starting the threads is the only allocation.
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
  // A tree node's box in SIMD lanes: x, y, z and a fourth lane that always overlaps (0).
  struct alignas(16) NodeBox {
    float lo[4], hi[4];
  };

  void detect(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
              std::span<const std::uint32_t> triangles, std::vector<TrianglePair>& pairs,
              int threads = 1);

 private:
  // One leaf's triangles in SIMD lanes: their boxes and welded vertex ids (lanes past the list's
  // end hold an empty box, which overlaps nothing).
  struct alignas(16) LeafLanes {
    float lo[3][kLeafSize], hi[3][kLeafSize];
    std::uint32_t vertex[3][kLeafSize];
  };
  // A piece of the descent: self(a) when a == b, else cross(a, b) of two overlapping nodes;
  // both `height` levels above the leaves.
  struct Task {
    std::uint32_t a, b, height;
  };
  // What the descent reads and where one thread's pairs go.
  struct Context {
    std::span<const glm::vec3> positions;
    std::span<const std::uint32_t> indices;
    std::vector<TrianglePair>& out;
  };

  void build_layout(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                    std::span<const std::uint32_t> triangles);
  void refit(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
             int threads);
  // The descent (cross: of nodes whose boxes overlap); pairs appended to context.out, each
  // pair once, in no order.
  void self(std::uint32_t node, std::uint32_t height, Context& context) const;
  void cross(std::uint32_t a, std::uint32_t b, std::uint32_t height, Context& context) const;
  // Leaf a's triangles against leaf b's (a == b: the leaf's own pairs).
  void leaf_pairs(std::uint32_t a, std::uint32_t b, Context& context) const;
  // Splits the top of the descent into at least `wanted` tasks (fewer when the tree is small).
  void split_tasks(std::size_t wanted);

  const std::uint32_t* built_triangles_ = nullptr;  // the list the layout was built for
  std::size_t built_size_ = 0;
  const std::uint32_t* built_indices_ = nullptr;
  std::vector<std::uint32_t> order_;  // triangle ids in leaf order (Morton)
  std::vector<LeafLanes> leaves_;     // per leaf
  std::vector<NodeBox> nodes_;        // implicit tree: root 1, children 2n and 2n + 1
  std::uint32_t leaf_count_ = 0, leaf_base_ = 1, height_ = 0;  // leaves at [leaf_base_, 2 ×)
  std::vector<Task> tasks_, next_tasks_;
  std::vector<std::vector<TrianglePair>> found_;  // per thread
};

}  // namespace sweepd::deform
