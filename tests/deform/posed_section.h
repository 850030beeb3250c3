// Test helper: areas of a posed mesh's cross-sections (the loop around a point), used to
// compare how much of a limb's section each deformation method keeps at a bent or twisted joint.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "deform/cross_section.h"
#include "deform/ellipse_fit.h"
#include "deform/mesh_topology.h"
#include "deform/model.h"

namespace sweepd::deform::test {

// The model's triangles over welded positions, so cut loops close at UV seams.
class WeldedMesh {
 public:
  explicit WeldedMesh(const Model& model) {
    std::size_t count = 0;
    id_ = weld_coincident_positions(model.positions, &count);
    positions_.resize(count);
    indices_.resize(model.indices.size());
    for (std::size_t i = 0; i < indices_.size(); ++i) indices_[i] = id_[model.indices[i]];
  }
  // Area of the closed loop that the plane (point, normal) cuts around `point` from the mesh
  // with these (unwelded, per model vertex) positions; 0 when there is none.
  float section_area(std::span<const glm::vec3> positions, glm::vec3 point, glm::vec3 normal) {
    for (std::size_t v = 0; v < positions.size(); ++v) positions_[id_[v]] = positions[v];
    const CrossSection section =
        cross_section(positions_, indices_, make_plane_frame(point, normal), point);
    if (!section.found || !section.closed || section.points_2d.size() < 3) return 0.0f;
    return fit_ellipse(section.points_2d).area;
  }

 private:
  std::vector<std::uint32_t> id_, indices_;
  std::vector<glm::vec3> positions_;
};

}  // namespace sweepd::deform::test
