// PartVolumeRegions: the closed mesh region of each body part (one per sweep) and its volume — the
// mesh triangles whose corners are bound to the part's sweep with a mean weight >= 0.5, every
// boundary loop (found once, on the welded mesh) capped by a fan to its centroid in the given
// positions, signed volume by the divergence theorem in double precision (positive for an
// outward-facing closed mesh). Volume preservation measures folding against it; the quality
// metrics report it.
// Inputs: positions: vertex_count() positions of the bound model's mesh (rest or posed).
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "deform/binding/bound_model.h"

namespace sweepd::deform {

// Signed volumes of closed part regions of one bound model.
class PartVolumeRegions {
 public:
  explicit PartVolumeRegions(const BoundModel& bound);
  // The closed region's signed volume for sweep s in these (per model vertex) positions.
  double volume(int sweep, std::span<const glm::vec3> positions) const;
  std::size_t triangle_count(int sweep) const { return regions_[sweep].triangles.size() / 3; }

 private:
  struct Region {
    std::vector<std::uint32_t> triangles;      // model vertex indices, 3 per triangle
    std::vector<std::uint32_t> loop_vertices;  // boundary loops, model vertex indices
    std::vector<std::uint32_t> loop_starts;    // loop i is [starts[i], starts[i+1])
  };
  std::vector<Region> regions_;
};

}  // namespace sweepd::deform
