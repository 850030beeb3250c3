// Each body a test checks, as other rigs would carry it (issue 48 item 6): the same mesh with its
// armature turned (tests/armature_turned_model.h: Blender's +90° about X, also at Mixamo's 0.01
// scale with the bones in centimetres; 90° about the
// vertical; and the whole body turned 90° about the vertical with its armature +90° about X,
// tests/turned_model.h), its joints renamed (tests/renamed_joints_model.h: a "mixamorig:" prefix,
// Unreal's names, meaningless names) and joints removed (tests/joints_removed_model.h: a spine
// joint, the clavicles, the toes, a neck joint, weights merged into the parent). Input: a body's
// name and model. Output: its variants, named "NAME armature +90° X" etc.; a variant the body's rig
// cannot have (no spine joint between pelvis and chest to drop, no clavicle, no toe, no neck joint
// below the head) is left out and named in `not_made`.
#pragma once

#include <glm/gtc/quaternion.hpp>
#include <string>
#include <vector>

#include "deform/model/model.h"
#include "deform/rig/rig_map.h"
#include "tests/armature_turned_model.h"
#include "tests/body_variants.h"
#include "tests/joints_removed_model.h"
#include "tests/renamed_joints_model.h"
#include "tests/turned_model.h"

namespace sweepd::test_models {

struct RigVariants {
  std::vector<BodyVariant> made;
  std::vector<std::string> not_made;  // "NAME no clavicles: the rig has none", ...
};

inline RigVariants rig_variants(const std::string& name, const deform::Model& model) {
  const deform::RigMap map = deform::detect_rig_map(model.skeleton);
  RigVariants variants;
  auto add = [&](const std::string& variant, deform::Model made) {
    variants.made.push_back({name + " " + variant, std::move(made)});
  };
  auto removed = [&](const std::string& variant, const std::vector<int>& joints,
                     const char* why_not) {
    if (joints.empty()) return variants.not_made.push_back(name + " " + variant + ": " + why_not);
    add(variant, without_joints(model, joints));
  };
  add("armature +90° X",
      armature_turned(model, glm::angleAxis(glm::radians(90.0f), glm::vec3(1, 0, 0))));
  add("armature +90° X at 0.01, bones in cm",
      armature_turned(model, glm::angleAxis(glm::radians(90.0f), glm::vec3(1, 0, 0)), 0.01f));
  add("armature 90° Y",
      armature_turned(model, glm::angleAxis(glm::radians(90.0f), glm::vec3(0, 1, 0))));
  add("turned 90°, armature +90° X",
      armature_turned(turned(model, 90.0f),
                      glm::angleAxis(glm::radians(90.0f), glm::vec3(1, 0, 0))));
  add("mixamorig: names", prefixed_joint_names(model, "mixamorig:"));
  add("unreal names", unreal_joint_names(model, map));
  add("meaningless names", meaningless_joint_names(model));
  const std::vector<int>& torso = map.torso.chain;
  removed("no spine joint",
          torso.size() >= 3 ? std::vector<int>{torso[torso.size() / 2]} : std::vector<int>{},
          "no joint between pelvis and chest");
  std::vector<int> clavicles, toes;
  for (int j : {map.left_arm.clavicle, map.right_arm.clavicle})
    if (j >= 0) clavicles.push_back(j);
  for (int j : {map.left_leg.toe, map.right_leg.toe})
    if (j >= 0) toes.push_back(j);
  removed("no clavicles", clavicles, "the rig has none");
  removed("no toes", toes.empty() ? toes : with_descendants(model.skeleton, toes),
          "the rig has none");
  const std::vector<int>& neck = map.neck.chain;  // ends with the head
  removed("no neck joint", neck.size() >= 2 ? std::vector<int>{neck.front()} : std::vector<int>{},
          "no joint between chest and head");
  return variants;
}

}  // namespace sweepd::test_models
