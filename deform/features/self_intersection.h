// Self-intersection of a skin region: which of its triangles cross each other (paper §4.3,
// the CPU reference that gpu::CollisionDetector must reproduce exactly).
//
// SelfIntersectionDetector::detect
//   Inputs:  positions  #V posed vertex positions
//            indices    3 per mesh triangle; two triangles that share an index are mesh
//                       neighbours and are never reported (pass seam-welded indices, e.g.
//                       CollisionRegions::welded_indices, so UV-seam copies count as shared)
//            triangles  #T ids of the triangles to test against each other (a collision region)
//   Output:  pairs      every {first < second} (triangle ids) whose closed triangles meet
//                       (deform/features/triangle_intersection.h), sorted, unique; cleared first.
//                       A triangle with a non-finite corner is in no pair.
// Broad phase: a uniform grid over the triangles' bounding boxes (cell size: the mean of the
// boxes' largest extents); each box pair is examined once, in the cell holding the lower
// corner of the boxes' overlap. Buffers are kept between calls: no allocation once warm.
#pragma once

#include <compare>
#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

namespace sweepd::deform {

struct TrianglePair {
  std::uint32_t first = 0;   // the smaller triangle id
  std::uint32_t second = 0;  // the larger triangle id
  auto operator<=>(const TrianglePair&) const = default;
};

// Axis-aligned box of one triangle (closed).
struct TriangleBox {
  glm::vec3 lo{0.0f}, hi{0.0f};
};

// The filters every detector applies before the exact test: the closed boxes overlap and the
// triangles share no vertex index.
// Inline: the broad phases call them per candidate, in their innermost loops.
inline bool boxes_overlap(const TriangleBox& a, const TriangleBox& b) {
  return a.lo.x <= b.hi.x && b.lo.x <= a.hi.x && a.lo.y <= b.hi.y && b.lo.y <= a.hi.y &&
         a.lo.z <= b.hi.z && b.lo.z <= a.hi.z;
}
inline bool share_a_vertex(std::span<const std::uint32_t> indices, std::uint32_t a,
                           std::uint32_t b) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (indices[3 * a + i] == indices[3 * b + j]) return true;
    }
  }
  return false;
}
TriangleBox triangle_box(std::span<const glm::vec3> positions,
                         std::span<const std::uint32_t> indices, std::uint32_t triangle);
// Whether all three corners of the triangle are finite.
bool finite_triangle(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                     std::uint32_t triangle);
// The exact test of mesh triangles a and b.
bool mesh_triangles_intersect(std::span<const glm::vec3> positions,
                              std::span<const std::uint32_t> indices, std::uint32_t a,
                              std::uint32_t b);

class SelfIntersectionDetector {
 public:
  void detect(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
              std::span<const std::uint32_t> triangles, std::vector<TrianglePair>& pairs);

 private:
  struct CellEntry {
    std::uint64_t cell;
    std::uint32_t slot;  // index into triangles
    bool operator<(const CellEntry& other) const {
      return cell != other.cell ? cell < other.cell : slot < other.slot;
    }
  };
  std::vector<TriangleBox> boxes_;
  std::vector<std::uint32_t> finite_slots_;  // the slots of the triangles with finite corners
  std::vector<CellEntry> entries_;
};

}  // namespace sweepd::deform
