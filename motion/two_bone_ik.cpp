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

// How far a limb of length `longest` reaches towards a target `distance` from its root: all the
// way up to `softness` short of its length, beyond that approaching the length exponentially
// (soft IK). A hard limit bends a near-straight limb's middle joint with a square-root
// singularity (a knee 1 mm short of straight stands about 2 cm out of line), so a target
// crossing the reach snapped the knee; the soft reach's slope falls smoothly from 1 to 0.
float soft_reach(float distance, float longest, float softness) {
  const float soft_from = longest - softness;
  if (softness <= 0.0f || distance <= soft_from) return std::min(distance, longest);
  return longest - softness * std::exp(-(distance - soft_from) / softness);
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
  const glm::vec3 upper_before = (middle - root) / bone, upper_after = glm::normalize(to);
  const glm::quat swing = shortest_arc(upper_before, upper_after);
  // The lower bone keeps its world rotation, but not so far that the middle joint folds past the
  // clip's own bend: folded further, the swept elbow or knee (its volume kept) bulged 3.6 cm
  // below the skinned samples the body floor lifts by (RiggedFigure without its middle spine
  // joint, knocked down: the elbow held at 125° where the clip bends it 98.5°). The excess is
  // turned out of the lower bone about the middle joint, towards the swung upper bone.
  glm::quat unfold = glm::identity<glm::quat>();
  if (limb.end >= 0) {
    const glm::vec3 lower = glm::vec3(world[limb.end][3]) - middle;
    if (glm::length(lower) > 1e-6f) {
      const glm::vec3 along = glm::normalize(lower);
      const float clip_bend = std::acos(std::clamp(glm::dot(upper_before, along), -1.0f, 1.0f));
      const float held_bend = std::acos(std::clamp(glm::dot(upper_after, along), -1.0f, 1.0f));
      const glm::vec3 axis = glm::cross(along, upper_after);
      if (held_bend > clip_bend && glm::length(axis) > 1e-6f)
        unfold = glm::angleAxis(held_bend - clip_bend, glm::normalize(axis));
    }
  }
  pose.local_rotations[limb.upper] = glm::normalize(
      glm::inverse(parent_rotation(skeleton, rotation, limb.upper)) * swing * rotation[limb.upper]);
  pose.local_rotations[limb.lower] =
      glm::normalize(glm::inverse(swing * parent_rotation(skeleton, rotation, limb.lower)) *
                     unfold * rotation[limb.lower]);
  // What hangs below (hand, foot) keeps its world rotation.
  if (limb.end >= 0 && unfold != glm::identity<glm::quat>())
    pose.local_rotations[limb.end] = glm::normalize(
        glm::inverse(unfold * parent_rotation(skeleton, rotation, limb.end)) * rotation[limb.end]);
}

void move_limb_end(const deform::Skeleton& skeleton, LimbJoints limb, glm::vec3 shift,
                   const std::vector<glm::mat4>& world, const std::vector<glm::quat>& rotation,
                   glm::vec3 bend_if_straight, float softness, deform::Pose& pose) {
  const glm::vec3 hip(world[limb.upper][3]), knee(world[limb.lower][3]), ankle(world[limb.end][3]);
  const float thigh = glm::distance(hip, knee), shin = glm::distance(knee, ankle);
  if (thigh < 1e-6f || shin < 1e-6f) return;
  // The end goes towards its target, along the direction from the root, as far as the soft
  // reach allows. Keeping the move across and clamping only the height (as this did) gave the
  // end's height a square-root singularity at the reach: an end 1 mm inside it moved 4 cm up or
  // down, and the knee with it (the knocked-down clip, a foot's fading shift along a leg
  // stretched on the floor).
  const float longest = (thigh + shin) * (1.0f - 1e-6f), shortest = std::abs(thigh - shin);
  glm::vec3 from_hip = ankle + shift - hip;
  const float across = glm::dot(glm::vec2(from_hip.x, from_hip.z), glm::vec2(from_hip.x, from_hip.z));
  if (across < shortest * shortest) {  // not through the root's blind spot around it
    const float blind = std::sqrt(shortest * shortest - across);
    if (from_hip.y > -blind && from_hip.y < blind) from_hip.y = -blind;
  }
  const glm::vec3 target = from_hip + hip;
  const glm::vec3 u = (knee - hip) / thigh, s = (ankle - knee) / shin;
  // The plane the limb bends in: its own, eased towards bend_if_straight's as it nears
  // straight, where its own is the clip's noise (a knee the clip holds within a few degrees of
  // straight, or overextended, turned its plane by tens of degrees between frames, and a knee
  // bent by the IK swung sideways with it: 5-6 cm in a frame, RiggedFigure in cmu_01_03).
  glm::vec3 axis = glm::cross(u, s);
  const glm::vec3 fallback = glm::cross(bend_if_straight, u);
  const float straightish = std::sin(glm::radians(kPlaneFromPoseBend));
  if (const float own = glm::length(axis); own < straightish && glm::length(fallback) > 1e-6f)
    axis += (straightish - own) * glm::normalize(fallback);
  if (glm::length(axis) < 1e-4f) {
    axis = fallback;
    if (glm::length(axis) < 1e-6f) return;
  }
  axis = glm::normalize(axis);
  const float reach =
      std::max(shortest, soft_reach(glm::distance(hip, target), longest, softness * (thigh + shin)));
  const float inner = std::acos(std::clamp(
      (thigh * thigh + shin * shin - reach * reach) / (2.0f * thigh * shin), -1.0f, 1.0f));
  // Straightened, then bent about the axis: exactly the bend the reach needs, whichever plane.
  const glm::quat knee_turn =
      glm::angleAxis(static_cast<float>(M_PI) - inner, axis) * shortest_arc(s, u);
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
