// Synthetic humanoid skeletons for the rig-map tests: a standing adult in metres, Y up, facing
// +Z (its left on +X), in a T- or A-pose, with the joint names of a chosen convention.
//
// HumanoidSpec names the joints; '*' in a limb name stands for the side's long spelling
// ("Left"), '%' for the short one ("L"). humanoid_nodes() lays the joints out as a list of
// (name, parent name, world position) that a test may edit (add twist bones, fingers, a root
// at the floor) before make_skeleton() turns it into a parents-first Skeleton with
// translation-only rest transforms.
#pragma once

#include <array>
#include <cmath>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "deform/model/skeleton.h"

namespace sweepd::test {

struct SkeletonNode {
  std::string name;
  std::string parent;  // "" for a root
  glm::vec3 world;     // rest position, metres
};

struct HumanoidSpec {
  std::vector<std::string> torso;  // pelvis first, up to the chest
  std::vector<std::string> neck;   // up to the head (last)
  std::array<std::string, 5> arm;  // clavicle, upper arm, forearm, hand, finger ("": none)
  std::array<std::string, 5> leg;  // hip link, thigh, shin, foot, toe ("": none)
  float arm_drop_degrees = 0.0f;   // 0: T-pose, 45: A-pose
  std::string long_left = "Left", long_right = "Right", short_left = "L", short_right = "R";
  std::string root{};  // a joint at the floor above the pelvis; "" for none
};

// The name with '*' / '%' replaced by the side's long / short spelling.
inline std::string sided(const HumanoidSpec& spec, const std::string& pattern, bool left) {
  std::string name;
  for (char c : pattern) {
    if (c == '*')
      name += left ? spec.long_left : spec.long_right;
    else if (c == '%')
      name += left ? spec.short_left : spec.short_right;
    else
      name += c;
  }
  return name;
}

inline std::vector<SkeletonNode> humanoid_nodes(const HumanoidSpec& spec) {
  std::vector<SkeletonNode> nodes;
  auto add = [&](const std::string& name, const std::string& parent, glm::vec3 world) {
    if (!name.empty()) nodes.push_back({name, parent, world});
    return name.empty() ? parent : name;
  };
  std::string parent = add(spec.root, "", glm::vec3(0.0f));
  const std::size_t torso_count = spec.torso.size();
  for (std::size_t i = 0; i < torso_count; ++i)  // pelvis at 0.95 m up to the chest at 1.35 m
    parent = add(
        spec.torso[i], parent,
        {0.0f, 0.95f + 0.40f * float(i) / float(std::max<std::size_t>(torso_count - 1, 1)), 0.0f});
  const std::string chest = parent;
  for (std::size_t i = 0; i < spec.neck.size(); ++i)  // neck from 1.45 m, head at 1.62 m
    parent =
        add(spec.neck[i], parent,
            {0.0f, 1.45f + 0.17f * float(i) / float(std::max<std::size_t>(spec.neck.size() - 1, 1)),
             0.01f});
  const float drop = glm::radians(spec.arm_drop_degrees);
  for (const bool left : {true, false}) {
    const float side = left ? 1.0f : -1.0f;
    const glm::vec3 arm_direction(side * std::cos(drop), -std::sin(drop), 0.0f);
    const glm::vec3 shoulder(side * 0.17f, 1.40f, 0.0f);
    const glm::vec3 elbow = shoulder + 0.28f * arm_direction;
    const glm::vec3 wrist = elbow + 0.25f * arm_direction;
    const glm::vec3 arm_at[5] = {
        {side * 0.03f, 1.38f, 0.02f}, shoulder, elbow, wrist, wrist + 0.09f * arm_direction};
    std::string arm = chest;
    for (int i = 0; i < 5; ++i) arm = add(sided(spec, spec.arm[i], left), arm, arm_at[i]);
    const glm::vec3 leg_at[5] = {{side * 0.03f, 0.93f, 0.0f},
                                 {side * 0.10f, 0.90f, 0.0f},
                                 {side * 0.10f, 0.50f, 0.02f},
                                 {side * 0.10f, 0.08f, -0.02f},
                                 {side * 0.10f, 0.02f, 0.11f}};
    std::string leg = spec.torso[0];
    for (int i = 0; i < 5; ++i) leg = add(sided(spec, spec.leg[i], left), leg, leg_at[i]);
  }
  return nodes;
}

// A parents-first Skeleton from nodes listed in any order (every parent must be listed).
inline deform::Skeleton make_skeleton(const std::vector<SkeletonNode>& nodes) {
  deform::Skeleton skeleton;
  std::vector<glm::vec3> world;
  std::vector<bool> placed(nodes.size(), false);
  for (bool progress = true; progress;) {
    progress = false;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      const int parent = nodes[i].parent.empty() ? -1 : skeleton.find(nodes[i].parent);
      if (placed[i] || (!nodes[i].parent.empty() && parent < 0)) continue;
      deform::Joint joint;
      joint.name = nodes[i].name;
      joint.parent = parent;
      joint.rest_translation = parent < 0 ? nodes[i].world : nodes[i].world - world[parent];
      skeleton.joints.push_back(joint);
      world.push_back(nodes[i].world);
      placed[i] = progress = true;
    }
  }
  return skeleton;
}

inline deform::Skeleton make_humanoid(const HumanoidSpec& spec) {
  return make_skeleton(humanoid_nodes(spec));
}

// The CMU MotionBuilder names of the shared male model (with one finger per hand), A-pose.
inline HumanoidSpec cmu_motionbuilder_spec() {
  return {{"Hips", "LowerBack", "Spine", "Spine1"},
          {"Neck", "Neck1", "Head"},
          {"*Shoulder", "*Arm", "*ForeArm", "*Hand", "*FingerBase"},
          {"%HipJoint", "*UpLeg", "*Leg", "*Foot", "*ToeBase"},
          45.0f};
}

}  // namespace sweepd::test
