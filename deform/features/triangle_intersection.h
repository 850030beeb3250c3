// Triangle–triangle intersection: the exact narrow phase of collision detection (paper §4.3).
//
// triangles_intersect(a, b)
//   Inputs:  a, b  3 corners each (float, any units)
//   Output:  true when the two CLOSED triangles share at least one point — crossing, touching at
//            a vertex or along an edge, or overlapping while coplanar.
// The test is Guigue–Devillers (2003): signs of 3D orientation determinants decide everything;
// coplanar pairs fall back to 2D edge/edge and vertex-in-triangle tests in the plane that the
// normal's largest component drops. Every determinant is evaluated in double from the float
// corners (differences and two-factor products are then exact; only the final sums round).
// gpu/collision_shaders.cpp evaluates the same determinants in float with a certified error
// bound and hands the pairs it cannot decide to this test, so CPU and GPU give the same pairs.
// Degenerate (zero-area) triangles intersect nothing.
//
// Mesh neighbours that share a vertex or an edge always touch; the callers
// (deform/features/self_intersection.h, gpu/collision.h) skip such pairs before calling this.
#pragma once

#include <glm/glm.hpp>
#include <span>

namespace sweepd::deform {

bool triangles_intersect(std::span<const glm::vec3, 3> a, std::span<const glm::vec3, 3> b);

}  // namespace sweepd::deform
