#include "deform/binding/section_key_ellipse.h"

#include <cmath>
#include <glm/gtc/quaternion.hpp>

namespace sweepd::deform {

KeyEllipse key_ellipse_in_plane(const PlaneFrame& plane, const EllipseFit& fit) {
  const glm::vec3 major = std::cos(fit.angle) * plane.x_axis + std::sin(fit.angle) * plane.y_axis;
  const glm::vec3 minor = glm::cross(plane.normal, major);
  KeyEllipse key;
  key.centre = plane.origin + fit.centre.x * plane.x_axis + fit.centre.y * plane.y_axis;
  key.orientation = glm::normalize(glm::quat_cast(glm::mat3(major, minor, plane.normal)));
  key.a = fit.a;
  key.b = fit.b;
  return key;
}

KeyEllipseFit fit_key_ellipse(std::span<const glm::vec3> positions,
                              std::span<const std::uint32_t> indices, const PlaneFrame& plane,
                              glm::vec3 link_point, std::optional<glm::vec3> fixed_centre) {
  KeyEllipseFit result;
  const CrossSection section = cross_section(positions, indices, plane, link_point);
  if (!section.found) return result;
  EllipseFitOptions options;
  if (fixed_centre) {
    const glm::vec3 d = *fixed_centre - plane.origin;
    options.fixed_centre = glm::vec2(glm::dot(d, plane.x_axis), glm::dot(d, plane.y_axis));
  }
  result.fit_2d = fit_polygon_ellipse(section.points_2d, options);
  result.closed_loop = section.closed;
  result.encloses_link_point = section.encloses_link_point;
  if (!result.fit_2d.valid) return result;
  result.valid = true;
  result.key = key_ellipse_in_plane(plane, result.fit_2d);
  return result;
}

}  // namespace sweepd::deform
