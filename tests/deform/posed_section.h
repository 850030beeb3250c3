// Test helper: areas of a posed mesh's cross-sections (the loop around a point), used to
// compare how much of a limb's section each deformation method keeps at a bent or twisted joint.
#pragma once

#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "deform/binding/cross_section.h"
#include "deform/binding/polygon_ellipse.h"
#include "deform/mesh/mesh_topology.h"
#include "deform/model/model.h"

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
    const CrossSection section = cut(positions, make_plane_frame(point, normal), point);
    if (!section.found || !section.closed || section.points_2d.size() < 3) return 0.0f;
    return fit_polygon_ellipse(section.points_2d).area;
  }
  // Area of the same loop clipped to the half-space dot(x - side_point, side_normal) >= 0: the
  // part of a limb's section on its own link's side of a bent joint's bisecting plane (a plane
  // near a strongly bent joint also cuts the other link, through the crease). Polygon area.
  float section_area_on_side(std::span<const glm::vec3> positions, glm::vec3 point,
                             glm::vec3 normal, glm::vec3 side_point, glm::vec3 side_normal) {
    const PlaneFrame frame = make_plane_frame(point, normal);
    const CrossSection section = cut(positions, frame, point);
    if (!section.found || !section.closed) return 0.0f;
    auto side = [&](glm::vec3 x) { return glm::dot(x - side_point, side_normal); };
    std::vector<glm::vec2> kept;  // Sutherland-Hodgman against one half-space, in plane coordinates
    auto in_plane = [&](glm::vec3 x) {
      return glm::vec2(glm::dot(x - frame.origin, frame.x_axis),
                       glm::dot(x - frame.origin, frame.y_axis));
    };
    const std::vector<glm::vec3>& loop = section.points;
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const glm::vec3 a = loop[i], b = loop[(i + 1) % loop.size()];
      const float sa = side(a), sb = side(b);
      if (sa >= 0.0f) kept.push_back(in_plane(a));
      if ((sa >= 0.0f) != (sb >= 0.0f)) kept.push_back(in_plane(a + (b - a) * (sa / (sa - sb))));
    }
    double twice_area = 0.0;
    for (std::size_t i = 0; i < kept.size(); ++i) {
      const glm::vec2 a = kept[i], b = kept[(i + 1) % kept.size()];
      twice_area += double(a.x) * b.y - double(b.x) * a.y;
    }
    return static_cast<float>(std::abs(twice_area) / 2.0);
  }

 private:
  // The loop around `point` cut from the mesh with these (unwelded) positions.
  CrossSection cut(std::span<const glm::vec3> positions, const PlaneFrame& frame, glm::vec3 point) {
    for (std::size_t v = 0; v < positions.size(); ++v) positions_[id_[v]] = positions[v];
    return cross_section(positions_, indices_, frame, point);
  }

  std::vector<std::uint32_t> id_, indices_;
  std::vector<glm::vec3> positions_;
};

}  // namespace sweepd::deform::test
