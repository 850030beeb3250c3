#include "deform/mesh/enclosed_volume.h"

namespace sweepd::deform {

double enclosed_volume(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                       std::span<const std::uint32_t> triangles) {
  double six_volume = 0.0;
  for (std::uint32_t t : triangles) {
    const glm::dvec3 p(positions[indices[3 * t]]), q(positions[indices[3 * t + 1]]),
        r(positions[indices[3 * t + 2]]);
    six_volume += glm::dot(p, glm::cross(q, r));
  }
  return six_volume / 6.0;
}

}  // namespace sweepd::deform
