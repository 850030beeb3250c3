// The rotation taking one direction onto another by the shortest arc (bone alignment in
// retargeting, the leg's swing in foot planting).
#pragma once

#include <cmath>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace sweepd::motion {

// u and v unit vectors; opposite ones give half a turn about an axis orthogonal to u.
inline glm::quat shortest_arc(const glm::vec3& u, const glm::vec3& v) {
  const float c = glm::dot(u, v);
  if (c < -1.0f + 1e-6f) {
    glm::vec3 axis = glm::cross(u, glm::vec3(1, 0, 0));
    if (glm::dot(axis, axis) < 1e-6f) axis = glm::cross(u, glm::vec3(0, 1, 0));
    return glm::angleAxis(static_cast<float>(M_PI), glm::normalize(axis));
  }
  const glm::vec3 axis = glm::cross(u, v);
  return glm::normalize(glm::quat(1.0f + c, axis.x, axis.y, axis.z));
}

}  // namespace sweepd::motion
