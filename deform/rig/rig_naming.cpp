#include "deform/rig/rig_naming.h"

#include <algorithm>
#include <cctype>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "deform/model/joint_paths.h"

namespace sweepd::deform {

namespace {

// Name patterns of one role; '*' stands for the side spelling ("Left", "l", ...).
using Patterns = std::vector<std::string_view>;

struct SideSpelling {
  std::string_view left, right;
};

struct NamingConvention {
  std::string_view name;
  std::string_view pelvis_prefix;  // the pelvis's raw name must start with this (any case)
  std::vector<SideSpelling> sides;
  Patterns pelvis, head;
  Patterns clavicle, upper_arm, forearm, hand;  // clavicle optional
  Patterns hip, thigh, shin, foot, toe;         // hip and toe optional
};

const std::vector<NamingConvention>& naming_conventions() {
  // Mixamo shares the MotionBuilder names, so it comes first and needs its prefix.
  // clang-format off
  static const std::vector<NamingConvention> table = {
      {"mixamo", "mixamorig", {{"Left", "Right"}}, {"Hips"}, {"Head"},
       {"*Shoulder"}, {"*Arm"}, {"*ForeArm"}, {"*Hand"},
       {}, {"*UpLeg"}, {"*Leg"}, {"*Foot"}, {"*ToeBase"}},
      {"cmu_motionbuilder", "", {{"Left", "Right"}, {"L", "R"}}, {"Hips"}, {"Head"},
       {"*Shoulder"}, {"*Arm"}, {"*ForeArm"}, {"*Hand"},
       {"*HipJoint"}, {"*UpLeg"}, {"*Leg"}, {"*Foot"}, {"*ToeBase"}},
      {"cmu_3dsmax", "", {{"Left", "Right"}, {"L", "R"}}, {"Hips"}, {"Head"},
       {"*Collar"}, {"*Shoulder"}, {"*Elbow"}, {"*Wrist"},
       {}, {"*Hip"}, {"*Knee"}, {"*Ankle"}, {"*Toe"}},
      {"unreal", "", {{"l", "r"}}, {"pelvis"}, {"head"},
       {"clavicle_*"}, {"upperarm_*"}, {"lowerarm_*"}, {"hand_*"},
       {}, {"thigh_*"}, {"calf_*"}, {"foot_*"}, {"ball_*"}},
      {"rigify", "", {{"L", "R"}}, {"spine"}, {"spine.006", "head"},
       {"shoulder.*"}, {"upper_arm.*"}, {"forearm.*"}, {"hand.*"},
       {}, {"thigh.*"}, {"shin.*"}, {"foot.*"}, {"toe.*"}},
      {"smpl", "", {{"L", "R"}, {"Left", "Right"}}, {"Pelvis"}, {"Head"},
       {"*_Collar"}, {"*_Shoulder"}, {"*_Elbow"}, {"*_Wrist"},
       {}, {"*_Hip"}, {"*_Knee"}, {"*_Ankle"}, {"*_Foot"}},
      {"vrm", "", {{"left", "right"}}, {"hips"}, {"head"},
       {"*Shoulder"}, {"*UpperArm"}, {"*LowerArm"}, {"*Hand"},
       {}, {"*UpperLeg"}, {"*LowerLeg"}, {"*Foot"}, {"*Toes"}},
  };
  // clang-format on
  return table;
}

std::string lowercase(std::string_view text) {
  std::string lower(text);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower;
}

// Joint names as matched: lower case, without a namespace ("mixamorig:", "Armature|") and
// without Blender's deform-bone prefix "def-".
class JointNameIndex {
 public:
  explicit JointNameIndex(const Skeleton& skeleton) {
    for (int j = 0; j < skeleton.size(); ++j) {
      std::string name = lowercase(skeleton.joints[j].name);
      if (const auto cut = name.find_last_of(":|"); cut != std::string::npos)
        name.erase(0, cut + 1);
      const bool deform_bone = name.starts_with("def-");
      if (deform_bone) name.erase(0, 4);
      // Where a rig has both "DEF-x" and "x" (Rigify's full rig), the deform bone wins.
      auto [it, inserted] = index_.try_emplace(name, j);
      if (!inserted && deform_bone) it->second = j;
    }
  }
  // The first joint matching a pattern, '*' replaced by `side`; -1 when none does.
  int find(const Patterns& patterns, std::string_view side = {}) const {
    for (std::string_view pattern : patterns) {
      std::string name(pattern);
      if (const auto star = name.find('*'); star != std::string::npos) name.replace(star, 1, side);
      if (auto it = index_.find(lowercase(name)); it != index_.end()) return it->second;
    }
    return -1;
  }

 private:
  std::unordered_map<std::string, int> index_;
};

// Finds a role on one side, trying each of the convention's side spellings.
int find_sided(const JointNameIndex& names, const NamingConvention& convention,
               const Patterns& patterns, bool left) {
  for (const SideSpelling& side : convention.sides)
    if (int j = names.find(patterns, left ? side.left : side.right); j >= 0) return j;
  return -1;
}

struct ConventionMatch {
  RigMap map;  // roles only; torso and neck chains filled by complete_chains
  int pelvis = -1;
  std::vector<std::string> missing;  // parts: "pelvis", "head", "left arm", ...
  int whole_limbs = 0;
};

ConventionMatch match_convention(const JointNameIndex& names, const Skeleton& skeleton,
                                 const NamingConvention& convention) {
  ConventionMatch match;
  match.map.convention = convention.name;
  match.pelvis = names.find(convention.pelvis);
  if (match.pelvis >= 0 &&
      !lowercase(skeleton.joints[match.pelvis].name).starts_with(convention.pelvis_prefix))
    match.pelvis = -1;
  if (match.pelvis < 0) match.missing.push_back("pelvis");
  match.map.neck.head = names.find(convention.head);
  if (match.map.neck.head < 0) match.missing.push_back("head");
  for (const bool left : {true, false}) {
    ArmJoints& arm = left ? match.map.left_arm : match.map.right_arm;
    arm.clavicle = find_sided(names, convention, convention.clavicle, left);
    arm.upper = find_sided(names, convention, convention.upper_arm, left);
    arm.lower = find_sided(names, convention, convention.forearm, left);
    arm.hand = find_sided(names, convention, convention.hand, left);
    const bool whole_arm = arm.upper >= 0 && arm.lower >= 0 && arm.hand >= 0;
    if (!whole_arm) match.missing.push_back(left ? "left arm" : "right arm");
    LegJoints& leg = left ? match.map.left_leg : match.map.right_leg;
    leg.hip = find_sided(names, convention, convention.hip, left);
    leg.upper = find_sided(names, convention, convention.thigh, left);
    leg.lower = find_sided(names, convention, convention.shin, left);
    leg.foot = find_sided(names, convention, convention.foot, left);
    leg.toe = find_sided(names, convention, convention.toe, left);
    const bool whole_leg = leg.upper >= 0 && leg.lower >= 0 && leg.foot >= 0;
    if (!whole_leg) match.missing.push_back(left ? "left leg" : "right leg");
    match.whole_limbs += int{whole_arm} + int{whole_leg};
  }
  return match;
}

// Fills the torso (pelvis up to the chest, where both arms and the head meet) and the neck
// (below the chest down to the head) from the hierarchy. Returns the problem, or "".
std::string complete_chains(ConventionMatch& match, const Skeleton& skeleton) {
  RigMap& map = match.map;
  const int head = map.neck.head;
  const int left_root = map.left_arm.clavicle >= 0 ? map.left_arm.clavicle : map.left_arm.upper;
  const int right_root = map.right_arm.clavicle >= 0 ? map.right_arm.clavicle : map.right_arm.upper;
  const int chest =
      common_ancestor(skeleton, common_ancestor(skeleton, left_root, right_root), head);
  map.torso.chain = path_down(skeleton, match.pelvis, chest);
  if (map.torso.chain.empty())
    return "the arms and the head do not meet below the pelvis '" +
           skeleton.joints[match.pelvis].name + "'";
  if (chest == head) return "the arms hang below the head '" + skeleton.joints[head].name + "'";
  map.neck.chain = path_down(skeleton, chest, head);
  map.neck.chain.erase(map.neck.chain.begin());
  return validate_rig_map(map, skeleton);
}

// "LeftArm/LeftForeArm/LeftHand, upperarm_l/lowerarm_l/hand_l, ..." over all conventions.
std::string expected_names(const std::string& part) {
  std::vector<std::string> examples;
  for (const NamingConvention& c : naming_conventions()) {
    const bool left = part.starts_with("left");
    const std::string_view side = left ? c.sides[0].left : c.sides[0].right;
    std::vector<const Patterns*> roles;
    if (part == "pelvis") roles = {&c.pelvis};
    if (part == "head") roles = {&c.head};
    if (part.ends_with("arm")) roles = {&c.upper_arm, &c.forearm, &c.hand};
    if (part.ends_with("leg")) roles = {&c.thigh, &c.shin, &c.foot};
    std::string example;
    for (const Patterns* role : roles) {
      std::string name(role->front());
      if (const auto star = name.find('*'); star != std::string::npos) name.replace(star, 1, side);
      example += (example.empty() ? "" : "/") + name;
    }
    const bool seen = std::any_of(examples.begin(), examples.end(), [&](const std::string& e) {
      return lowercase(e) == lowercase(example);
    });
    if (!seen) examples.push_back(example);
  }
  std::string text;
  for (const std::string& example : examples) text += (text.empty() ? "" : ", ") + example;
  return text;
}

std::string describe_missing(const ConventionMatch& match) {
  std::string text;
  for (const std::string& part : match.missing) {
    const bool single = part == "pelvis" || part == "head";
    text += (text.empty() ? "" : "; ") + ("no " + part + ": expected ") +
            (single ? "a joint like " : "joints like ") + expected_names(part);
  }
  return text;
}

}  // namespace

NamedRigMatch match_rig_naming(const Skeleton& skeleton) {
  const JointNameIndex names(skeleton);
  NamedRigMatch result;
  std::optional<ConventionMatch> closest;
  for (const NamingConvention& convention : naming_conventions()) {
    ConventionMatch match = match_convention(names, skeleton, convention);
    if (match.missing.empty()) {
      if (std::string why = complete_chains(match, skeleton); !why.empty()) {
        // Every name is there but the hierarchy disagrees: report it unless another fits.
        if (!result.looks_named) result.problem = std::string(convention.name) + " names: " + why;
        result.looks_named = true;
        continue;
      }
      result.map = std::move(match.map);
      return result;
    }
    if (!closest || match.missing.size() < closest->missing.size()) closest = std::move(match);
  }
  if (result.looks_named) return result;
  result.looks_named = closest->whole_limbs > 0;
  if (closest->missing.size() == 6) {  // not even a pelvis or head name: no convention at all
    result.problem = "no joint has a name of a known convention (";
    for (const NamingConvention& c : naming_conventions())
      result.problem += std::string(c.name) + (&c == &naming_conventions().back() ? ")" : ", ");
    return result;
  }
  result.problem = "joint names closest to the " + closest->map.convention + " convention, but " +
                   describe_missing(*closest);
  return result;
}

}  // namespace sweepd::deform
