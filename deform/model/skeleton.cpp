#include "deform/model/skeleton.h"

#include <glm/gtc/matrix_transform.hpp>

namespace sweepd::deform {

int Skeleton::find(const std::string& name) const {
  for (int j = 0; j < size(); ++j)
    if (joints[j].name == name) return j;
  return -1;
}

glm::mat4 Skeleton::local_rest_matrix(int j) const {
  const Joint& joint = joints[j];
  glm::mat4 m = glm::translate(glm::mat4(1.0f), joint.rest_translation);
  m = m * glm::mat4_cast(joint.rest_rotation);
  return glm::scale(m, joint.rest_scale);
}

std::vector<glm::mat4> Skeleton::world_rest_matrices() const {
  std::vector<glm::mat4> world(joints.size());
  for (int j = 0; j < size(); ++j) {
    const glm::mat4 local = local_rest_matrix(j);
    world[j] = joints[j].parent < 0 ? local : world[joints[j].parent] * local;
  }
  return world;
}

std::vector<int> Skeleton::children(int j) const {
  std::vector<int> result;
  for (int c = 0; c < size(); ++c)
    if (joints[c].parent == j) result.push_back(c);
  return result;
}

std::string Skeleton::validate() const {
  for (int j = 0; j < size(); ++j) {
    const int parent = joints[j].parent;
    if (parent >= j)
      return "joint " + std::to_string(j) + " ('" + joints[j].name + "') has parent " +
             std::to_string(parent) + ", not an earlier joint";
    if (parent < -1)
      return "joint " + std::to_string(j) + " has invalid parent " + std::to_string(parent);
  }
  return {};
}

}  // namespace sweepd::deform
