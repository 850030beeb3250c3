// fit_key_ellipse: a key ellipse fitted to a mesh cross-section (paper §3.2) — cuts the mesh
// with the plane, keeps the link's loop (cross_section), fits the area-moment ellipse in the
// plane (fit_polygon_ellipse) and lifts it back to 3D.
//
// Inputs:  positions (V), indices (3F), the cutting plane (its normal becomes the key's N, so
//          point it along the sweep), the link point (selects the loop), and optionally a fixed
//          centre (a joint; projected onto the plane) about which the moments are taken.
// Output:  KeyEllipseFit: the key ellipse (R = [major, minor, normal], a >= b) and what the fit
//          saw; valid == false when the plane misses the mesh or the loop has no area.
// The major axis is the one with a non-negative plane x_axis component (EllipseFit::angle in
// (-π/2, π/2]): fit neighbouring keys of one sweep in plane frames with the same x_hint, or
// their orientations may differ by a half turn about N (which twists the sweep).
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <span>

#include "deform/binding/cross_section.h"
#include "deform/binding/polygon_ellipse.h"
#include "deform/sweep/key_ellipse.h"

namespace sweepd::deform {

struct KeyEllipseFit {
  bool valid = false;
  KeyEllipse key;
  EllipseFit fit_2d;                 // in the plane frame's (x_axis, y_axis) coordinates
  bool closed_loop = false;          // false: the loop was an open chain (closed for the fit)
  bool encloses_link_point = false;  // false: the loop nearest to the link point was used
};

// The key ellipse of a 2D fit in a plane frame.
KeyEllipse key_ellipse_in_plane(const PlaneFrame& plane, const EllipseFit& fit);

KeyEllipseFit fit_key_ellipse(std::span<const glm::vec3> positions,
                              std::span<const std::uint32_t> indices, const PlaneFrame& plane,
                              glm::vec3 link_point,
                              std::optional<glm::vec3> fixed_centre = std::nullopt);

}  // namespace sweepd::deform
