// Test helper: a legless cut of a rigged model, made in memory — every joint of the legs and
// feet goes (by the model's detected rig map), with every vertex whose skin weights are mostly
// on them; the weights left on them move to the pelvis; triangles that lost a corner go, and
// so do vertices no triangle uses any more.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "deform/model/model.h"
#include "deform/rig/rig_map.h"

namespace sweepd::deform::test {

inline bool is_leg(BodyPart part) {
  return part == BodyPart::kLeftLeg || part == BodyPart::kRightLeg || part == BodyPart::kLeftFoot ||
         part == BodyPart::kRightFoot;
}

// The model without its legs: every joint of the legs and feet goes, and every vertex whose
// skin weights are mostly on them; the weights left on them move to the pelvis; triangles that
// lost a corner go, and so do vertices no triangle uses any more.
inline Model legless_cut(const Model& model) {
  const RigMap rig = detect_rig_map(model.skeleton);
  const std::vector<BodyPart> part = label_joints(rig, model.skeleton);
  const int pelvis = rig.torso.pelvis();
  std::vector<int> new_joint(model.skeleton.size(), -1);
  Model cut;
  cut.name = model.name + " (legless)";
  for (int j = 0; j < model.skeleton.size(); ++j) {
    if (is_leg(part[j])) continue;
    new_joint[j] = cut.skeleton.size();
    Joint joint = model.skeleton.joints[j];
    if (joint.parent >= 0) joint.parent = new_joint[joint.parent];
    cut.skeleton.joints.push_back(joint);
  }
  auto leg_weight = [&](std::size_t v) {
    float weight = 0.0f;
    for (int k = 0; k < kInfluences; ++k)
      if (is_leg(part[model.skin_joints[v][k]])) weight += model.skin_weights[v][k];
    return weight;
  };
  std::vector<std::uint8_t> used(model.vertex_count(), 0);
  std::vector<std::uint32_t> triangles;
  for (std::size_t t = 0; t < model.indices.size(); t += 3) {
    const bool keep = std::all_of(model.indices.begin() + t, model.indices.begin() + t + 3,
                                  [&](std::uint32_t v) { return leg_weight(v) <= 0.5f; });
    if (!keep) continue;
    for (int c = 0; c < 3; ++c) used[model.indices[t + c]] = 1;
    triangles.insert(triangles.end(), model.indices.begin() + t, model.indices.begin() + t + 3);
  }
  std::vector<std::uint32_t> new_vertex(model.vertex_count(), 0);
  for (std::size_t v = 0; v < model.vertex_count(); ++v) {
    if (!used[v]) continue;
    new_vertex[v] = static_cast<std::uint32_t>(cut.positions.size());
    cut.positions.push_back(model.positions[v]);
    cut.normals.push_back(model.normals[v]);
    if (model.has_uvs()) cut.uvs.push_back(model.uvs[v]);
    std::array<std::uint16_t, kInfluences> joints{};
    std::array<float, kInfluences> weights{};
    int n = 0;
    for (int k = 0; k < kInfluences; ++k) {
      const float w = model.skin_weights[v][k];
      const int j = is_leg(part[model.skin_joints[v][k]]) ? pelvis : model.skin_joints[v][k];
      if (w == 0.0f) continue;
      int slot = 0;
      while (slot < n && joints[slot] != new_joint[j]) ++slot;
      if (slot == n) joints[n++] = static_cast<std::uint16_t>(new_joint[j]);
      weights[slot] += w;
    }
    cut.skin_joints.push_back(joints);
    cut.skin_weights.push_back(weights);
  }
  for (std::uint32_t v : triangles) cut.indices.push_back(new_vertex[v]);
  return cut;
}

}  // namespace sweepd::deform::test
