// A model turned about the vertical through the origin, mesh and skeleton (every root joint):
// the same body built facing another way (a character modelled facing +X, a Blender armature and
// mesh turned 90°), for tests that check nothing assumes the model faces +Z.
// Input: a Model (by value), the turn in degrees. Output: the turned Model.
#pragma once

#include <glm/gtc/quaternion.hpp>

#include "deform/model/model.h"

namespace sweepd::test_models {

inline deform::Model turned(deform::Model model, float degrees) {
  const glm::quat turn = glm::angleAxis(glm::radians(degrees), glm::vec3(0, 1, 0));
  for (glm::vec3& p : model.positions) p = turn * p;
  for (glm::vec3& n : model.normals) n = turn * n;
  for (deform::Joint& joint : model.skeleton.joints) {
    if (joint.parent >= 0) continue;  // every root: OpenPose's legs are roots of their own
    joint.rest_translation = turn * joint.rest_translation;
    joint.rest_rotation = turn * joint.rest_rotation;
  }
  return model;
}

}  // namespace sweepd::test_models
