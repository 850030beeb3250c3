#include "motion/two_bone_ik.h"

#include <algorithm>
#include <cmath>

#include "motion/shortest_arc.h"

namespace sweepd::motion {

std::vector<glm::quat> world_rotations(const deform::Skeleton& skeleton, const deform::Pose& pose) {
  std::vector<glm::quat> world(skeleton.joints.size());
  for (int j = 0; j < skeleton.size(); ++j) {
    const int parent = skeleton.joints[j].parent;
    world[j] = parent < 0 ? pose.local_rotations[j] : world[parent] * pose.local_rotations[j];
  }
  return world;
}

namespace {

glm::quat parent_rotation(const deform::Skeleton& skeleton, const std::vector<glm::quat>& rotation,
                          int joint) {
  const int parent = skeleton.joints[joint].parent;
  return parent < 0 ? glm::identity<glm::quat>() : rotation[parent];
}

}  // namespace

void move_limb_middle(const deform::Skeleton& skeleton, LimbJoints limb, glm::vec3 shift,
                      const std::vector<glm::mat4>& world, const std::vector<glm::quat>& rotation,
                      deform::Pose& pose) {
  const glm::vec3 root(world[limb.upper][3]), middle(world[limb.lower][3]);
  const float bone = glm::distance(root, middle);
  if (bone < 1e-6f) return;
  // The middle joint's target across, at the height nearest its own that the bone reaches.
  glm::vec3 to = middle + glm::vec3(shift.x, 0.0f, shift.z) - root;
  const float across = glm::dot(glm::vec2(to.x, to.z), glm::vec2(to.x, to.z));
  if (across < bone * bone) {
    const float height = std::sqrt(bone * bone - across);
    to.y = to.y < 0.0f ? -height : height;
  }
  if (glm::length(to) < 1e-6f) return;
  const glm::quat swing = shortest_arc((middle - root) / bone, glm::normalize(to));
  pose.local_rotations[limb.upper] = glm::normalize(
      glm::inverse(parent_rotation(skeleton, rotation, limb.upper)) * swing * rotation[limb.upper]);
  pose.local_rotations[limb.lower] = glm::normalize(
      glm::inverse(swing * parent_rotation(skeleton, rotation, limb.lower)) * rotation[limb.lower]);
}

void move_limb_end(const deform::Skeleton& skeleton, LimbJoints limb, glm::vec3 shift,
                   const std::vector<glm::mat4>& world, const std::vector<glm::quat>& rotation,
                   glm::vec3 bend_if_straight, deform::Pose& pose) {
  const glm::vec3 hip(world[limb.upper][3]), knee(world[limb.lower][3]), ankle(world[limb.end][3]);
  const float thigh = glm::distance(hip, knee), shin = glm::distance(knee, ankle);
  if (thigh < 1e-6f || shin < 1e-6f) return;
  // The end moves across by the shift, then up or down, as far towards the shift's rise as the
  // limb reaches: the heights where the root-to-end distance lies within the limb's range.
  const float longest = (thigh + shin) * (1.0f - 1e-6f), shortest = std::abs(thigh - shin);
  glm::vec3 from_hip = ankle + glm::vec3(shift.x, 0.0f, shift.z) - hip;
  float across = glm::dot(glm::vec2(from_hip.x, from_hip.z), glm::vec2(from_hip.x, from_hip.z));
  if (across >= longest * longest) {
    // Beyond the limb's reach across: the end goes as far towards the shift as the limb
    // reaches, not nowhere (doing nothing here dropped a foot's whole shift for a frame, and
    // the knee jumped by several centimetres where the shift came back).
    const glm::vec2 start(ankle.x - hip.x, ankle.z - hip.z);
    const glm::vec2 end(from_hip.x, from_hip.z);
    const float limit = longest * longest * (1.0f - 1e-4f);
    if (glm::dot(start, start) >= limit) return;
    float lo = 0.0f, hi = 1.0f;  // the largest part of the shift that stays within reach
    for (int i = 0; i < 24; ++i) {
      const float mid = 0.5f * (lo + hi);
      const glm::vec2 at = glm::mix(start, end, mid);
      (glm::dot(at, at) < limit ? lo : hi) = mid;
    }
    const glm::vec2 at = glm::mix(start, end, lo);
    from_hip.x = at.x, from_hip.z = at.y;
    across = glm::dot(at, at);
  }
  float rise = shift.y;
  const float deepest = std::sqrt(longest * longest - across);
  rise = std::clamp(rise, -from_hip.y - deepest, -from_hip.y + deepest);
  if (across < shortest * shortest) {  // not through the root's blind spot around it
    const float blind = std::sqrt(shortest * shortest - across);
    if (from_hip.y + rise > -blind && from_hip.y + rise < blind) rise = -from_hip.y - blind;
  }
  const glm::vec3 target = from_hip + hip + glm::vec3(0.0f, rise, 0.0f);
  const glm::vec3 u = (knee - hip) / thigh, s = (ankle - knee) / shin;
  glm::vec3 axis = glm::cross(u, s);
  const float bend = std::atan2(glm::length(axis), glm::dot(u, s));
  if (glm::length(axis) < 1e-4f) {
    axis = glm::cross(bend_if_straight, u);
    if (glm::length(axis) < 1e-6f) return;
  }
  axis = glm::normalize(axis);
  const float reach = std::clamp(glm::distance(hip, target), shortest, longest);
  const float inner = std::acos(std::clamp(
      (thigh * thigh + shin * shin - reach * reach) / (2.0f * thigh * shin), -1.0f, 1.0f));
  const glm::quat knee_turn = glm::angleAxis(static_cast<float>(M_PI) - inner - bend, axis);
  const glm::vec3 moved = knee + knee_turn * (ankle - knee);
  if (glm::length(moved - hip) < 1e-6f || glm::length(target - hip) < 1e-6f) return;
  const glm::quat swing = shortest_arc(glm::normalize(moved - hip), glm::normalize(target - hip));
  const auto parent_rotation = [&](int j) {
    return motion::parent_rotation(skeleton, rotation, j);
  };
  // Joints between these follow their parents: the upper bone swings, the lower turns about the
  // middle joint in the swung frame, and the end keeps its world rotation.
  pose.local_rotations[limb.upper] =
      glm::normalize(glm::inverse(parent_rotation(limb.upper)) * swing * rotation[limb.upper]);
  pose.local_rotations[limb.lower] =
      glm::normalize(glm::inverse(parent_rotation(limb.lower)) * knee_turn * rotation[limb.lower]);
  pose.local_rotations[limb.end] = glm::normalize(
      glm::inverse(swing * knee_turn * parent_rotation(limb.end)) * rotation[limb.end]);
}

}  // namespace sweepd::motion
