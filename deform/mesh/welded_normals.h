// WeldedNormals: area-weighted unit vertex normals of a deformed triangle mesh, shared by the
// vertices that coincide in the rest mesh (seam copies), recomputed per frame without allocating.
//
// Construction (once): the rest positions (to weld coincident vertices) and the triangle
// indices (3 per triangle). compute(): positions of the deformed mesh (rest vertex count) →
// normals (as many): the normalised sum of the cross products of the triangles around the
// welded vertex, (0, 1, 0) where that sum is zero. The per-frame triangle normals live in the
// caller's `scratch` (resized to scratch_count() on first use), so one WeldedNormals is shared
// read-only by threads that each own their scratch (deform/job/model_runtime.h).
// On one thread, each triangle's area normal is added to its corners' welded sums (a scatter:
// the fastest on one core). On several, two passes split over the threads (run_in_vertex_blocks):
// every triangle's area normal, then every vertex gathers its welded vertex's triangles in
// ascending order — the order the scatter adds them — so results are bit-identical for any thread
// count.
#pragma once

#include <algorithm>
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
               std::vector<FloatLanes>& scratch, int threads = 1) const;
  // The gather's triangle normals and its zero entry, or the scatter's welded sums (padded to 4).
  std::size_t scratch_count() const {
    return std::max(corner_vertex_.size() / 3 + 1, (first_more_.size() + 2) / 4 * 4);
  }

 private:
  void scatter(std::span<const glm::vec3> positions, std::span<glm::vec3> normals,
               FloatLanes* sums) const;
  void gather(std::span<const glm::vec3> positions, std::span<glm::vec3> normals,
              FloatLanes* area_normals, int threads) const;

  std::vector<std::uint32_t> corner_vertex_;  // per triangle corner: its vertex
  std::vector<std::uint32_t> corner_welded_;  // per triangle corner: its welded vertex
  std::vector<std::uint32_t> welded_;         // per vertex: its welded vertex
  // A welded vertex's triangles: kSlots per vertex (a fixed count: the gather loop does not
  // branch), the rest in more_[first_more_[w], first_more_[w + 1]).
  static constexpr std::size_t kSlots = 8;
  std::vector<std::uint32_t> slots_;
  std::vector<std::uint32_t> first_more_;
  std::vector<std::uint32_t> more_;
};

}  // namespace sweepd::deform
