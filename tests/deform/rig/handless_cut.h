// Test helper: a rigged model whose hands lose their joints, made in memory — every joint of
// both hands goes (the hand joint and everything below it, by the model's detected rig map), and
// the weights on them move to the forearm joint, so the forearm's bone carries the hand as
// OpenPose's does. Every vertex and triangle stays.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "deform/model/model.h"
#include "deform/rig/rig_map.h"

namespace sweepd::deform::test {

inline Model handless_cut(const Model& model) {
  const RigMap rig = detect_rig_map(model.skeleton);
  const std::vector<BodyPart> part = label_joints(rig, model.skeleton);
  // Per joint: the joint its weights go to (itself, or for a hand joint the forearm's).
  std::vector<int> owner(model.skeleton.size());
  for (int j = 0; j < model.skeleton.size(); ++j)
    owner[j] = part[j] == BodyPart::kLeftHand    ? rig.left_arm.lower
               : part[j] == BodyPart::kRightHand ? rig.right_arm.lower
                                                 : j;
  std::vector<int> new_joint(model.skeleton.size(), -1);
  Model cut = model;
  cut.name = model.name + " (handless)";
  cut.skeleton.joints.clear();
  for (int j = 0; j < model.skeleton.size(); ++j) {
    if (owner[j] != j) continue;
    new_joint[j] = cut.skeleton.size();
    Joint joint = model.skeleton.joints[j];
    if (joint.parent >= 0) joint.parent = new_joint[joint.parent];
    cut.skeleton.joints.push_back(joint);
  }
  for (std::size_t v = 0; v < model.vertex_count(); ++v) {
    std::array<std::uint16_t, kInfluences> joints{};
    std::array<float, kInfluences> weights{};
    int n = 0;
    for (int k = 0; k < kInfluences; ++k) {
      const float w = model.skin_weights[v][k];
      if (w == 0.0f) continue;
      const int j = new_joint[owner[model.skin_joints[v][k]]];
      int slot = 0;
      while (slot < n && joints[slot] != j) ++slot;
      if (slot == n) joints[n++] = static_cast<std::uint16_t>(j);
      weights[slot] += w;
    }
    cut.skin_joints[v] = joints;
    cut.skin_weights[v] = weights;
  }
  return cut;
}

}  // namespace sweepd::deform::test
