// cross_section: cuts a triangle mesh with a plane and returns the one intersection loop that
// belongs to a given link (paper §3.2: key ellipses are fitted to cross-sections cut by planes
// orthogonal to a link; a plane through the shoulder also cuts the torso, so the loop enclosing
// the link point — or else the nearest one — is kept).
//
// Inputs:  positions (V), indices (3F, triangles), the cutting plane as a PlaneFrame, and the
//          link point (3D; projected onto the plane for the enclosure test).
// Output:  CrossSection: the loop as 3D points and as 2D coordinates (x_axis, y_axis) in the
//          plane frame, without a repeated closing point.
// Robustness: a vertex exactly on the plane counts as being on the positive side, so every
// triangle has 0 or 2 crossing edges and loops are chained through shared mesh edges
// (topologically, never by comparing positions); coincident consecutive points are dropped.
// Open chains (mesh holes, non-manifold edges) are returned with closed == false.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

namespace sweepd::deform {

struct PlaneFrame {
  glm::vec3 origin{0.0f};
  glm::vec3 x_axis{1.0f, 0.0f, 0.0f};  // unit, in the plane
  glm::vec3 y_axis{0.0f, 1.0f, 0.0f};  // unit, in the plane, = cross(normal, x_axis)
  glm::vec3 normal{0.0f, 0.0f, 1.0f};  // unit
};

// An orthonormal frame for the plane through origin with this normal (normalised here). The
// x axis is the projection of x_hint onto the plane, or of some other axis where that vanishes.
PlaneFrame make_plane_frame(glm::vec3 origin, glm::vec3 normal,
                            glm::vec3 x_hint = glm::vec3(1.0f, 0.0f, 0.0f));

struct CrossSection {
  bool found = false;                // the plane cuts the mesh, so a loop was chosen
  bool closed = false;               // the chosen loop closes
  bool encloses_link_point = false;  // chosen because it encloses the link point (else nearest)
  int loop_count = 0;                // how many separate loops/chains the plane produced
  std::vector<glm::vec3> points;     // the chosen loop, in order
  std::vector<glm::vec2> points_2d;  // the same, in plane coordinates
};

// Throws std::invalid_argument when indices.size() % 3 != 0 or an index is out of range.
CrossSection cross_section(std::span<const glm::vec3> positions,
                           std::span<const std::uint32_t> indices, const PlaneFrame& plane,
                           glm::vec3 link_point);

}  // namespace sweepd::deform
