// fit_polygon_ellipse: the ellipse of a closed polygon's area moments (paper §3.2, fitting key
// ellipses to mesh cross-sections).
//
// The polygon (the region it encloses, either orientation) is integrated with Green's theorem
// for its area A, centroid and second moments M about the centre c (the centroid, or a fixed
// point such as the joint). A solid ellipse with half-axes a, b has moments (A/4)·diag(a², b²)
// in its own frame, so the eigenvectors of M give the axes and a, b ∝ sqrt of its eigenvalues,
// scaled so that π a b = A (the ellipse keeps the polygon's area).
// Inputs:  polygon — m >= 3 vertices of a closed polygon (last joined to first, not repeated).
// Output:  EllipseFit; valid == false (other fields zero) when the polygon has no area.
#pragma once

#include <glm/glm.hpp>
#include <optional>
#include <span>

namespace sweepd::deform {

struct EllipseFit {
  bool valid = false;
  glm::vec2 centre{0.0f};
  float angle = 0.0f;  // of the major axis from +x, in (-π/2, π/2]
  float a = 0.0f;      // major half-axis, a >= b > 0
  float b = 0.0f;      // minor half-axis
  float area = 0.0f;   // |polygon area| (= π a b)
  // RMS over the polygon vertices of ρ - 1, with ρ = sqrt(u²/a² + v²/b²) in the ellipse frame:
  // the radial distance of a vertex from the ellipse relative to the ellipse's radius in that
  // direction (0 when every vertex lies on the ellipse).
  float fit_error = 0.0f;
};

struct EllipseFitOptions {
  // When set, the ellipse is centred here (e.g. at the joint) and the moments are taken about it.
  std::optional<glm::vec2> fixed_centre;
};

EllipseFit fit_polygon_ellipse(std::span<const glm::vec2> polygon,
                               const EllipseFitOptions& options = {});

}  // namespace sweepd::deform
