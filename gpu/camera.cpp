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
  const glm::vec3 centre = 0.5f * (low + high);
  const float radius = std::max(0.5f * glm::length(high - low), 1e-6f);
  const float vertical_fov = glm::radians(vertical_fov_degrees);
  const float horizontal_fov = 2.0f * std::atan(std::tan(0.5f * vertical_fov) * aspect);
  const float distance = radius / std::sin(0.5f * std::min(vertical_fov, horizontal_fov));
  Camera camera;
  camera.view = glm::lookAt(centre + glm::vec3(0.0f, 0.0f, distance), centre, {0.0f, 1.0f, 0.0f});
  camera.projection =
      glm::perspective(vertical_fov, aspect, std::max(distance - 2.0f * radius, 0.01f * distance),
                       distance + 2.0f * radius);
  return camera;
}

Camera box_camera(glm::vec3 centre, glm::vec3 half_extents, glm::vec3 towards_eye, float aspect,
                  float vertical_fov_degrees) {
  const float tan_vertical = std::tan(0.5f * glm::radians(vertical_fov_degrees));
  const float tan_horizontal = tan_vertical * aspect;
  // The box's near face is half_extents.z closer than the centre: fit its corners there.
  const float distance =
      std::max(half_extents.x / tan_horizontal, half_extents.y / tan_vertical) + half_extents.z;
  const glm::vec3 eye_direction = glm::normalize(towards_eye);
  const glm::vec3 up = std::abs(eye_direction.y) > 0.999f ? glm::vec3(0.0f, 0.0f, 1.0f)
                                                          : glm::vec3(0.0f, 1.0f, 0.0f);
  Camera camera;
  camera.view = glm::lookAt(centre + distance * eye_direction, centre, up);
  camera.projection = glm::perspective(glm::radians(vertical_fov_degrees), aspect,
                                       std::max(distance - 2.0f * half_extents.z, 0.01f * distance),
                                       distance + 2.0f * half_extents.z);
  return camera;
}

}  // namespace sweepd::gpu
