#include "io/rest_transform.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/quaternion.hpp>
#include <iterator>

namespace sweepd::io {

bool decompose_rest_transform(const glm::dmat4& m, deform::Joint& joint) {
  glm::dvec3 scale(glm::length(glm::dvec3(m[0])), glm::length(glm::dvec3(m[1])),
                   glm::length(glm::dvec3(m[2])));
  if (!(scale.x > 0.0 && scale.y > 0.0 && scale.z > 0.0)) return false;
  if (glm::determinant(glm::dmat3(m)) < 0.0) scale.x = -scale.x;
  const glm::dmat3 rotation(glm::dvec3(m[0]) / scale.x, glm::dvec3(m[1]) / scale.y,
                            glm::dvec3(m[2]) / scale.z);
  joint.rest_translation = glm::vec3(glm::dvec3(m[3]));
  joint.rest_rotation = glm::quat(glm::normalize(glm::quat_cast(rotation)));
  joint.rest_scale = glm::vec3(scale);
  return true;
}

bool finite_rest_transform(const deform::Joint& joint) {
  const float values[10] = {joint.rest_translation.x, joint.rest_translation.y,
                            joint.rest_translation.z, joint.rest_rotation.x,
                            joint.rest_rotation.y,    joint.rest_rotation.z,
                            joint.rest_rotation.w,    joint.rest_scale.x,
                            joint.rest_scale.y,       joint.rest_scale.z};
  return std::all_of(std::begin(values), std::end(values),
                     [](float v) { return std::isfinite(v); });
}

glm::dmat3 normal_matrix(const glm::dmat4& skin) {
  const glm::dmat3 a(skin);
  return glm::dmat3(glm::cross(a[1], a[2]), glm::cross(a[2], a[0]), glm::cross(a[0], a[1]));
}

}  // namespace sweepd::io
