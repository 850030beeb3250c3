// WeldedNormals: area-weighted unit vertex normals of a deformed triangle mesh, shared by the
// vertices that coincide in the rest mesh (seam copies), recomputed per frame without allocating.
//
// Construction (once): the rest positions (to weld coincident vertices) and the triangle
// indices (3 per triangle). compute(): positions of the deformed mesh (rest vertex count) →
// normals (as many): the normalised sum of the cross products of the triangles around the
// welded vertex, (0, 1, 0) where that sum is zero. The per-frame sums live in the caller's
// `sums` (resized to sum_count() on first use), so one WeldedNormals is shared read-only by
// threads that each own their sums (deform/job/model_runtime.h).
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "deform/simd/float_lanes.h"

namespace sweepd::deform {

class WeldedNormals {
 public:
  WeldedNormals(std::span<const glm::vec3> rest_positions, std::span<const std::uint32_t> indices);

  void compute(std::span<const glm::vec3> positions, std::span<glm::vec3> normals,
               std::vector<FloatLanes>& sums) const;
  std::size_t sum_count() const { return sum_count_; }

 private:
  std::vector<std::uint32_t> corner_vertex_;  // per triangle corner: its vertex
  std::vector<std::uint32_t> corner_welded_;  // per triangle corner: its welded vertex
  std::vector<std::uint32_t> welded_;         // per vertex: its welded vertex
  std::size_t sum_count_ = 0;                 // welded vertices, padded to a multiple of 4
};

}  // namespace sweepd::deform
