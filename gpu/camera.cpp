#include "gpu/camera.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

namespace sweepd::gpu {

Camera front_camera(std::span<const glm::vec3> positions, float aspect,
                    float vertical_fov_degrees) {
  glm::vec3 low(0.0f), high(0.0f);
  if (!positions.empty()) low = high = positions.front();
  for (const glm::vec3& p : positions) {
    low = glm::min(low, p);
    high = glm::max(high, p);
  }
  return sphere_camera(0.5f * (low + high), std::max(0.5f * glm::length(high - low), 1e-6f),
                       {0.0f, 0.0f, 1.0f}, aspect, vertical_fov_degrees);
}

Camera sphere_camera(glm::vec3 centre, float radius, glm::vec3 towards_eye, float aspect,
                     float vertical_fov_degrees) {
  const float vertical_fov = glm::radians(vertical_fov_degrees);
  const float horizontal_fov = 2.0f * std::atan(std::tan(0.5f * vertical_fov) * aspect);
  const float distance = radius / std::sin(0.5f * std::min(vertical_fov, horizontal_fov));
  const glm::vec3 eye_direction = glm::normalize(towards_eye);
  const glm::vec3 up = std::abs(eye_direction.y) > 0.999f ? glm::vec3(0.0f, 0.0f, 1.0f)
                                                          : glm::vec3(0.0f, 1.0f, 0.0f);
  Camera camera;
  camera.view = glm::lookAt(centre + distance * eye_direction, centre, up);
  camera.projection =
      glm::perspective(vertical_fov, aspect, std::max(distance - 2.0f * radius, 0.01f * distance),
                       distance + 2.0f * radius);
  return camera;
}

}  // namespace sweepd::gpu
