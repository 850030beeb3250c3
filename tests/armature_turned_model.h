// A model whose joints' own frames are turned while the body stays where it is: what a glTF
// exporter writes when the armature node is turned (Blender's +90° about X, its Z-up bones
// under a Y-up scene) and the bones inside are turned back, so joints and mesh keep their world
// places. Every joint's world rest rotation W becomes W * turn; rest positions, mesh and skin
// weights are unchanged (uniform joint scales assumed, as every shared body has). With a scale
// (Mixamo's 0.01 armature, its bones in centimetres) the root's rest scale takes it and every
// other joint's rest translation is divided by it, so the world rest pose is still the same.
// Input: a Model (by value), the turn, the armature's scale. Output: the Model with its joints'
// frames turned (and scaled).
#pragma once

#include <glm/gtc/quaternion.hpp>

#include "deform/model/model.h"

namespace sweepd::test_models {

inline deform::Model armature_turned(deform::Model model, glm::quat turn, float scale = 1.0f) {
  const glm::quat back = glm::inverse(turn);
  for (deform::Joint& joint : model.skeleton.joints) {
    if (joint.parent < 0) {
      joint.rest_rotation = joint.rest_rotation * turn;  // W * turn at the root
      joint.rest_scale *= scale;
    } else {
      // Local L' = turn^-1 * L * turn: its translation is in the parent's turned frame.
      joint.rest_translation = back * joint.rest_translation / scale;
      joint.rest_rotation = back * joint.rest_rotation * turn;
    }
  }
  return model;
}

}  // namespace sweepd::test_models
