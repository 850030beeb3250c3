#include "deform/binding/polygon_ellipse.h"

#include <cmath>
#include <numbers>

namespace sweepd::deform {

EllipseFit fit_polygon_ellipse(std::span<const glm::vec2> polygon,
                               const EllipseFitOptions& options) {
  EllipseFit fit;
  const std::size_t m = polygon.size();
  if (m < 3) return fit;
  // Work about the first vertex (or the fixed centre) in double to limit cancellation.
  const glm::dvec2 origin =
      options.fixed_centre ? glm::dvec2(*options.fixed_centre) : glm::dvec2(polygon[0]);
  double area2 = 0.0, cx = 0.0, cy = 0.0, ixx = 0.0, iyy = 0.0, ixy = 0.0;
  for (std::size_t k = 0; k < m; ++k) {
    const glm::dvec2 p = glm::dvec2(polygon[k]) - origin;
    const glm::dvec2 q = glm::dvec2(polygon[(k + 1) % m]) - origin;
    const double cross = p.x * q.y - q.x * p.y;
    area2 += cross;
    cx += (p.x + q.x) * cross;
    cy += (p.y + q.y) * cross;
    ixx += (p.x * p.x + p.x * q.x + q.x * q.x) * cross;
    iyy += (p.y * p.y + p.y * q.y + q.y * q.y) * cross;
    ixy += (p.x * q.y + 2.0 * p.x * p.y + 2.0 * q.x * q.y + q.x * p.y) * cross;
  }
  const double area = 0.5 * area2;
  if (!(std::abs(area) > 0.0) || !std::isfinite(area)) return fit;
  // Signed sums over the signed area: both signs cancel, so orientation does not matter.
  glm::dvec2 centroid(cx / (3.0 * area2), cy / (3.0 * area2));  // ∫x dA / A = Σ(..)/(6A)
  double sxx = ixx / (12.0 * area), syy = iyy / (12.0 * area), sxy = ixy / (24.0 * area);
  glm::dvec2 centre(0.0);  // relative to origin
  if (!options.fixed_centre) {
    // Parallel-axis theorem: moments about the centroid.
    centre = centroid;
    sxx -= centroid.x * centroid.x;
    syy -= centroid.y * centroid.y;
    sxy -= centroid.x * centroid.y;
  }
  // Eigen-decomposition of the symmetric 2x2 matrix [sxx sxy; sxy syy].
  const double mean = 0.5 * (sxx + syy);
  const double radius = std::hypot(0.5 * (sxx - syy), sxy);
  const double major = mean + radius, minor = mean - radius;
  if (!(minor > 0.0)) return fit;
  double angle = 0.5 * std::atan2(2.0 * sxy, sxx - syy);  // in (-π/2, π/2]
  if (angle <= -0.5 * std::numbers::pi) angle += std::numbers::pi;
  // Solid ellipse: variance a²/4 along the major axis. Rescale to the polygon's area.
  double a = 2.0 * std::sqrt(major), b = 2.0 * std::sqrt(minor);
  const double scale = std::sqrt(std::abs(area) / (std::numbers::pi * a * b));
  a *= scale;
  b *= scale;

  const glm::dvec2 axis(std::cos(angle), std::sin(angle));
  double error2 = 0.0;
  for (const glm::vec2& vertex : polygon) {
    const glm::dvec2 d = glm::dvec2(vertex) - origin - centre;
    const double u = glm::dot(d, axis), v = axis.x * d.y - axis.y * d.x;
    const double rho = std::sqrt((u * u) / (a * a) + (v * v) / (b * b));
    error2 += (rho - 1.0) * (rho - 1.0);
  }
  fit.valid = true;
  fit.centre = glm::vec2(origin + centre);
  fit.angle = static_cast<float>(angle);
  fit.a = static_cast<float>(a);
  fit.b = static_cast<float>(b);
  fit.area = static_cast<float>(std::abs(area));
  fit.fit_error = static_cast<float>(std::sqrt(error2 / static_cast<double>(m)));
  return fit;
}

}  // namespace sweepd::deform
