#include "deform/rig/rig_map.h"

#include <algorithm>
#include <cstdio>
#include <optional>
#include <stdexcept>

#include "deform/model/joint_paths.h"

namespace sweepd::deform {

namespace {

void append_if_present(std::vector<int>& chain, int joint) {
  if (joint >= 0) chain.push_back(joint);
}

std::string joint_name(const Skeleton& skeleton, int j) {
  if (j < 0 || j >= skeleton.size()) return "#" + std::to_string(j);
  return "'" + skeleton.joints[j].name + "'";
}

struct LimbRole {
  const char* name;
  int joint;
  bool required;
};

// Both limbs list their roles root first with the hand or foot at this index.
constexpr int kHandOrFootRole = 3;

// An arm may end without a hand joint: OpenPose's forearm joint carries the hand.
std::vector<LimbRole> roles_of(const ArmJoints& arm) {
  return {{"clavicle", arm.clavicle, false},
          {"upper", arm.upper, true},
          {"lower", arm.lower, true},
          {"hand", arm.hand, false}};
}

std::vector<LimbRole> roles_of(const LegJoints& leg) {
  return {{"hip", leg.hip, false},
          {"upper", leg.upper, true},
          {"lower", leg.lower, true},
          {"foot", leg.foot, true},
          {"toe", leg.toe, false}};
}

std::string out_of_range(const std::string& part, int j, const Skeleton& skeleton) {
  return part + ": joint id " + std::to_string(j) + " is out of range (skeleton has " +
         std::to_string(skeleton.size()) + " joints)";
}

// Checks one limb: required roles present, ids in range, each role strictly below the one
// before it.
std::string validate_limb(const std::string& part, const std::vector<LimbRole>& roles,
                          const Skeleton& skeleton) {
  int previous = -1;
  for (const LimbRole& role : roles) {
    if (role.joint == -1) {
      if (role.required) return part + ": has no " + role.name + " joint";
      continue;
    }
    if (role.joint < 0 || role.joint >= skeleton.size())
      return out_of_range(part, role.joint, skeleton);
    if (previous >= 0 && !is_strict_ancestor(skeleton, previous, role.joint))
      return part + ": " + joint_name(skeleton, role.joint) + " is not below " +
             joint_name(skeleton, previous) + " in the hierarchy";
    previous = role.joint;
  }
  return {};
}

std::string validate_path(const std::string& part, const std::vector<int>& chain, int first_parent,
                          const Skeleton& skeleton) {
  for (std::size_t i = 0; i < chain.size(); ++i) {
    if (chain[i] < 0 || chain[i] >= skeleton.size()) return out_of_range(part, chain[i], skeleton);
    const int expected_parent = i == 0 ? first_parent : chain[i - 1];
    if (expected_parent >= 0 && skeleton.joints[chain[i]].parent != expected_parent)
      return part + ": " + joint_name(skeleton, chain[i]) + " is not a child of " +
             joint_name(skeleton, expected_parent) + " (the chain must follow the hierarchy)";
  }
  return {};
}

// The root above `joint` (itself when it is one).
int top_of(const Skeleton& skeleton, int joint) {
  while (skeleton.joints[joint].parent >= 0) joint = skeleton.joints[joint].parent;
  return joint;
}

std::string names_of(const std::vector<int>& chain, const Skeleton& skeleton) {
  std::string text;
  for (int j : chain) text += (text.empty() ? "" : " > ") + skeleton.joints[j].name;
  return text;
}

std::string describe_roles(const std::vector<LimbRole>& roles, const Skeleton& skeleton) {
  std::string text;
  for (const LimbRole& role : roles)
    if (role.joint >= 0)
      text += (text.empty() ? "" : ", ") + std::string(role.name) + " " +
              skeleton.joints[role.joint].name;
  return text;
}

}  // namespace

std::vector<int> ArmJoints::chain() const {
  std::vector<int> chain;
  append_if_present(chain, clavicle);
  for (int j : {upper, lower}) chain.push_back(j);
  append_if_present(chain, hand);
  return chain;
}

std::vector<int> LegJoints::chain() const {
  std::vector<int> chain;
  append_if_present(chain, hip);
  for (int j : {upper, lower, foot}) chain.push_back(j);
  append_if_present(chain, toe);
  return chain;
}

std::vector<int> RigMap::skinned_part_roots() const {
  return {neck.head, left_arm.hand, right_arm.hand, left_leg.foot, right_leg.foot};
}

std::vector<int> RigMap::torso_sweep_chain() const {
  std::vector<int> chain = torso.chain;
  if (chain.size() == 1 && !neck.chain.empty()) chain.push_back(neck.chain.front());
  return chain;
}

const char* to_string(BodyPart part) {
  switch (part) {
    case BodyPart::kNone:
      return "none";
    case BodyPart::kTorso:
      return "torso";
    case BodyPart::kNeck:
      return "neck";
    case BodyPart::kHead:
      return "head";
    case BodyPart::kLeftArm:
      return "left arm";
    case BodyPart::kRightArm:
      return "right arm";
    case BodyPart::kLeftHand:
      return "left hand";
    case BodyPart::kRightHand:
      return "right hand";
    case BodyPart::kLeftLeg:
      return "left leg";
    case BodyPart::kRightLeg:
      return "right leg";
    case BodyPart::kLeftFoot:
      return "left foot";
    case BodyPart::kRightFoot:
      return "right foot";
  }
  return "unknown";
}

const char* to_string(RigPart part) {
  constexpr const char* kNames[] = {"torso",     "head",     "left arm",
                                    "right arm", "left leg", "right leg"};
  return kNames[static_cast<int>(part)];
}

const char* to_string(PartFinding finding) {
  switch (finding) {
    case PartFinding::kGiven:
      return "given";
    case PartFinding::kByName:
      return "by name";
    case PartFinding::kByShape:
      return "by shape";
    case PartFinding::kAbsent:
      return "absent";
  }
  return "unknown";
}

std::string validate_rig_map(const RigMap& map, const Skeleton& skeleton) {
  const std::vector<int>& torso = map.torso.chain;
  if (torso.empty()) return "torso: has no joints (needs at least the pelvis)";
  if (std::string why = validate_path("torso", torso, -1, skeleton); !why.empty()) return why;
  const bool head_absent = map.neck.chain.empty() && map.neck.head == -1;
  if (!head_absent) {
    if (map.neck.chain.empty()) return "neck: has no joints (needs at least the head)";
    if (std::string why = validate_path("neck", map.neck.chain, map.torso.chest(), skeleton);
        !why.empty())
      return why;
    if (map.neck.head != map.neck.chain.back())
      return "neck: the head " + joint_name(skeleton, map.neck.head) +
             " is not the last joint of the neck chain";
  }
  const struct {
    const char* part;
    std::vector<LimbRole> roles;
  } limbs[] = {{"left arm", roles_of(map.left_arm)},
               {"right arm", roles_of(map.right_arm)},
               {"left leg", roles_of(map.left_leg)},
               {"right leg", roles_of(map.right_leg)}};
  std::vector<std::string> part_of(skeleton.size());
  auto claim = [&](const std::string& part, int j) -> std::string {
    if (!part_of[j].empty())
      return part + ": joint " + joint_name(skeleton, j) + " is already used by the " + part_of[j];
    part_of[j] = part;
    return {};
  };
  for (int j : torso)
    if (std::string why = claim("torso", j); !why.empty()) return why;
  for (int j : map.neck.chain)
    if (std::string why = claim("neck", j); !why.empty()) return why;
  for (const auto& [part, roles] : limbs) {
    const bool absent = std::all_of(roles.begin(), roles.end(),
                                    [](const LimbRole& role) { return role.joint == -1; });
    if (absent) continue;
    if (std::string why = validate_limb(part, roles, skeleton); !why.empty()) return why;
    const int root = roles[0].joint >= 0 ? roles[0].joint : roles[1].joint;
    if (!is_strict_ancestor(skeleton, map.torso.pelvis(), root) &&
        top_of(skeleton, root) == top_of(skeleton, map.torso.pelvis()))
      return std::string(part) + ": " + joint_name(skeleton, root) +
             " is neither below the pelvis " + joint_name(skeleton, map.torso.pelvis()) +
             " nor in a tree of its own beside it";
    for (const LimbRole& role : roles)
      if (role.joint >= 0)
        if (std::string why = claim(part, role.joint); !why.empty()) return why;
  }
  return {};
}

std::vector<BodyPart> label_joints(const RigMap& map, const Skeleton& skeleton) {
  std::vector<BodyPart> own(skeleton.size(), BodyPart::kNone);
  auto set = [&](int j, BodyPart part) {
    if (j >= 0 && j < skeleton.size()) own[j] = part;
  };
  for (int j : map.torso.chain) set(j, BodyPart::kTorso);
  for (int j : map.neck.chain) set(j, BodyPart::kNeck);
  set(map.neck.head, BodyPart::kHead);
  const struct {
    std::vector<LimbRole> roles;
    BodyPart limb, end;
  } limbs[] = {{roles_of(map.left_arm), BodyPart::kLeftArm, BodyPart::kLeftHand},
               {roles_of(map.right_arm), BodyPart::kRightArm, BodyPart::kRightHand},
               {roles_of(map.left_leg), BodyPart::kLeftLeg, BodyPart::kLeftFoot},
               {roles_of(map.right_leg), BodyPart::kRightLeg, BodyPart::kRightFoot}};
  for (const auto& [roles, limb, end] : limbs) {
    for (int i = 0; i < kHandOrFootRole; ++i) set(roles[i].joint, limb);
    set(roles[kHandOrFootRole].joint, end);  // a toe after it inherits the foot
  }
  std::vector<BodyPart> labels(skeleton.size(), BodyPart::kNone);
  for (int j = 0; j < skeleton.size(); ++j) {
    const int parent = skeleton.joints[j].parent;
    const bool inherits = own[j] == BodyPart::kNone && parent >= 0 && parent < j;
    labels[j] = inherits ? labels[parent] : own[j];
  }
  return labels;
}

glm::vec3 rest_torso_up(const RigMap& map, std::span<const glm::mat4> world_rest) {
  auto position = [&](int joint) { return glm::vec3(world_rest[joint][3]); };
  const glm::vec3 spine = position(map.torso.chest()) - position(map.torso.pelvis());
  if (map.torso.chain.size() >= 2 && glm::length(spine) > 1e-4f) return glm::normalize(spine);
  auto mean = [&](std::initializer_list<int> joints) {
    glm::vec3 sum(0.0f);
    int count = 0;
    for (int j : joints)
      if (j >= 0) sum += position(j), ++count;
    return count > 0 ? std::optional<glm::vec3>(sum / static_cast<float>(count)) : std::nullopt;
  };
  auto shoulder = [](const ArmJoints& arm) { return arm.clavicle >= 0 ? arm.clavicle : arm.upper; };
  const std::optional<glm::vec3> above = mean(
      {shoulder(map.left_arm), shoulder(map.right_arm), map.neck.chain.empty() ? -1 : map.neck.chain[0]});
  const std::optional<glm::vec3> below = mean({map.left_leg.upper, map.right_leg.upper});
  const glm::vec3 from = below ? *below : position(map.torso.pelvis());
  if (above && glm::length(*above - from) > 1e-4f) return glm::normalize(*above - from);
  return glm::vec3(0.0f, 1.0f, 0.0f);
}

BodyAxes rest_body_axes(const RigMap& map, std::span<const glm::mat4> world_rest) {
  auto position = [&](int joint) { return glm::vec3(world_rest[joint][3]); };
  BodyAxes axes;
  axes.up = rest_torso_up(map, world_rest);
  glm::vec3 lateral(1.0f, 0.0f, 0.0f);
  axes.left_from = "neither arms nor thighs: the glTF convention's +X";
  if (!map.left_arm.absent() && !map.right_arm.absent()) {
    lateral = position(map.left_arm.upper) - position(map.right_arm.upper);
    axes.left_from = "the right upper arm to the left";
  } else if (!map.left_leg.absent() && !map.right_leg.absent()) {
    lateral = position(map.left_leg.upper) - position(map.right_leg.upper);
    axes.left_from = "the right thigh to the left";
  }
  axes.left = glm::normalize(lateral - glm::dot(lateral, axes.up) * axes.up);
  axes.forward = glm::cross(axes.left, axes.up);
  return axes;
}

std::string describe(const RigMap& map, const Skeleton& skeleton) {
  auto how = [&](RigPart part) {
    const PartDetection& found = map.found[static_cast<int>(part)];
    std::string text = std::string(" [") + to_string(found.finding);
    // Where some names were read, say why they did not settle a part the shape found.
    if (found.finding == PartFinding::kByShape && map.convention != "topological")
      text += ": " + found.note;
    return text + "]\n";
  };
  auto limb = [&](RigPart part, const std::vector<LimbRole>& roles, bool absent) {
    return std::string(to_string(part)) + ": " +
           (absent ? std::string("absent, skinned") : describe_roles(roles, skeleton)) + how(part);
  };
  std::string text = "convention: " + map.convention + "\n" +
                     "torso: " + names_of(map.torso.chain, skeleton) + how(RigPart::kTorso);
  text += map.has_head() ? "neck: " + names_of(map.neck.chain, skeleton) + " (head " +
                               skeleton.joints[map.neck.head].name + ")" + how(RigPart::kHead)
                         : "neck and head: absent, skinned" + how(RigPart::kHead);
  // The facing found (motion/retarget.h turns a model built facing another way than its clip).
  const BodyAxes axes = rest_body_axes(map, skeleton.world_rest_matrices());
  char facing[200];
  std::snprintf(facing, sizeof facing,
                "facing: forward (%.2f, %.2f, %.2f), up (%.2f, %.2f, %.2f); left from %s, "
                "up from %s\n",
                axes.forward.x, axes.forward.y, axes.forward.z, axes.up.x, axes.up.y, axes.up.z,
                axes.left_from,
                map.torso.chain.size() >= 2 ? "the pelvis to the chest" : "the hips to the shoulders");
  text += facing;
  text += limb(RigPart::kLeftArm, roles_of(map.left_arm), map.left_arm.absent());
  text += limb(RigPart::kRightArm, roles_of(map.right_arm), map.right_arm.absent());
  text += limb(RigPart::kLeftLeg, roles_of(map.left_leg), map.left_leg.absent());
  text += limb(RigPart::kRightLeg, roles_of(map.right_leg), map.right_leg.absent());
  for (const std::string& warning : map.warnings) text += "warning: " + warning + "\n";
  return text;
}

}  // namespace sweepd::deform
