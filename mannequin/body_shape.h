// BodyShape: an implicit body made of "parts" — tapered capsules with elliptic cross-sections
// (the procedural mannequin's torso, limbs, hands, feet and head) — joined by a smooth union.
//
// A part runs along a straight axis from `start` to `end`. Its cross-section orthogonal to the
// axis is an ellipse with half-axes `side` (along side axis) and `depth` (along the depth
// axis, the part's `front` direction made orthogonal to the axis), centred `depth_offset` in
// front of the axis; the three vary smoothly along the axis between the given sections. Both
// ends are closed by half-ellipsoids reaching `start_cap` / `end_cap` beyond the end points.
// The side axis is cross(axis, depth axis): for a part pointing up and facing +Z it is +X.
//
// value(p) < 0 inside, > 0 outside; it approximates a distance in metres near the surface and
// is a function of p alone, so a grid can be sampled block by block without cracks.
#pragma once

#include <glm/glm.hpp>
#include <span>
#include <string>
#include <vector>

namespace sweepd::mannequin {

struct PartSection {
  float t = 0.0f;             // position along the axis, 0 at start, 1 at end
  float side = 0.0f;          // half-axis along the side axis (metres)
  float depth = 0.0f;         // half-axis along the depth axis (metres)
  float depth_offset = 0.0f;  // centre shift along the depth axis (metres, + is front)
};

struct BodyPart {
  std::string name;
  int skin_chain = 0;  // which skinning chain the part's skin follows (owner's choice)
  glm::vec3 start{0.0f};
  glm::vec3 end{0.0f, 1.0f, 0.0f};
  glm::vec3 front{0.0f, 0.0f, 1.0f};  // must not be parallel to end - start
  std::vector<PartSection> sections;  // t ascending; at least one
  float start_cap = 0.0f;             // half-ellipsoid lengths beyond the ends (metres, > 0)
  float end_cap = 0.0f;
};

// Position of a point relative to one part's axis.
struct PartCoordinates {
  float axial = 0.0f;  // fraction along the axis including the caps: 0 at the start cap's tip,
                       // 1 at the end cap's tip (clamped)
  float angle = 0.0f;  // around the axis in [0, 1); 0 and 1 at the back (-depth axis)
};

class BodyShape {
 public:
  // blend_radius: size of the smooth union's fillets (metres). minimum_half_axis: every
  // cross-section half-axis is raised to at least this (so a coarse grid still sees thin parts).
  BodyShape(std::vector<BodyPart> parts, float blend_radius, float minimum_half_axis);

  int part_count() const { return static_cast<int>(parts_.size()); }
  const BodyPart& part(int i) const { return parts_[i].part; }
  // Axis-aligned box holding the whole surface.
  glm::vec3 lower_bound() const { return lower_; }
  glm::vec3 upper_bound() const { return upper_; }
  float blend_radius() const { return blend_radius_; }

  float value(const glm::vec3& p) const;
  // One part's own field (< 0 inside the part), ignoring the others.
  float part_value(int part, const glm::vec3& p) const;
  PartCoordinates part_coordinates(int part, const glm::vec3& p) const;
  // Central-difference gradient of value() with step h.
  glm::vec3 gradient(const glm::vec3& p, float h) const;

  // values[n] = value(points[n]); false (values untouched) when no part reaches the box
  // [lo, hi], which is then entirely outside. Signature of a marching_tetrahedra BlockField.
  bool evaluate_block(const glm::vec3& lo, const glm::vec3& hi, std::span<const glm::vec3> points,
                      std::span<float> values) const;

 private:
  struct PreparedPart {
    BodyPart part;
    glm::vec3 axis{0.0f}, side_axis{0.0f}, depth_axis{0.0f};
    float length = 0.0f;
    glm::vec3 reach_lower{0.0f}, reach_upper{0.0f};  // box outside which the part is ignored
  };
  PartSection section_at(const PreparedPart& part, float t) const;
  float prepared_value(const PreparedPart& part, const glm::vec3& p) const;
  float union_value(std::span<const int> parts, const glm::vec3& p) const;

  std::vector<PreparedPart> parts_;
  std::vector<int> all_parts_;  // 0 .. part_count() - 1
  float blend_radius_;
  float outside_value_;  // value where no part reaches
  glm::vec3 lower_{0.0f}, upper_{0.0f};
};

}  // namespace sweepd::mannequin
