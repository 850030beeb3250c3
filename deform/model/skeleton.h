// Skeleton: the joint hierarchy of a rigged model, in rest pose.
//
// Joints are stored parents-first (parent index < own index, roots have -1), so forward
// kinematics is one pass in order. Every joint's rest transform is local to its parent;
// world rest transforms follow from them. Loaders reorder the file's joints to this order.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <string>
#include <vector>

namespace sweepd::deform {

struct Joint {
  std::string name;
  int parent = -1;                      // index into Skeleton::joints, -1 for a root
  glm::vec3 rest_translation{0.0f};     // local to the parent
  glm::quat rest_rotation{1, 0, 0, 0};  // local to the parent (w, x, y, z)
  glm::vec3 rest_scale{1.0f};           // local to the parent
};

struct Skeleton {
  std::vector<Joint> joints;

  int size() const { return static_cast<int>(joints.size()); }
  // Index of the joint with this exact name, or -1.
  int find(const std::string& name) const;
  // Local rest matrix (T * R * S) of joint j.
  glm::mat4 local_rest_matrix(int j) const;
  // World rest matrices of every joint (parents-first pass).
  std::vector<glm::mat4> world_rest_matrices() const;
  // Children of joint j, in index order.
  std::vector<int> children(int j) const;
  // Empty when the parents-first order and parent indices hold; otherwise the reason.
  std::string validate() const;
};

}  // namespace sweepd::deform
