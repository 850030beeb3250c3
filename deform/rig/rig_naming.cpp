#include "deform/rig/rig_naming.h"

#include <algorithm>
#include <cctype>
#include <optional>
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
  std::string_view pelvis_marker;  // the pelvis's raw name must contain this (any case)
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
      {"biped", "bip", {{"L", "R"}}, {"Pelvis"}, {"Head"},
       {"* Clavicle"}, {"* UpperArm"}, {"* Forearm"}, {"* Hand"},
       {}, {"* Thigh"}, {"* Calf"}, {"* Foot"}, {"* Toe0"}},
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
      {"vrm", "", {{"L", "R"}}, {"J_Bip_C_Hips"}, {"J_Bip_C_Head"},
       {"J_Bip_*_Shoulder"}, {"J_Bip_*_UpperArm"}, {"J_Bip_*_LowerArm"}, {"J_Bip_*_Hand"},
       {}, {"J_Bip_*_UpperLeg"}, {"J_Bip_*_LowerLeg"}, {"J_Bip_*_Foot"}, {"J_Bip_*_ToeBase"}},
      {"daz_genesis", "", {{"l", "r"}}, {"hip"}, {"head"},
       {"*Collar"}, {"*ShldrBend", "*Shldr"}, {"*ForearmBend", "*ForeArm"}, {"*Hand"},
       {}, {"*ThighBend", "*Thigh"}, {"*Shin"}, {"*Foot"}, {"*Toe"}},
      {"makehuman", "", {{"L", "R"}}, {"root"}, {"head"},
       {"clavicle.*"}, {"upperarm01.*"}, {"lowerarm01.*"}, {"wrist.*"},
       {"pelvis.*"}, {"upperleg01.*"}, {"lowerleg01.*"}, {"foot.*"}, {"toe1-1.*"}},
  };
  // clang-format on
  return table;
}

std::string lowercase(std::string_view text) {
  std::string lower(text);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower;
}

bool is_digits(std::string_view text) {
  return !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
    return std::isdigit(static_cast<unsigned char>(c));
  });
}

// The name as matched, and how much its layer is preferred (0 best): lower case, without a
// namespace ("ns:", "Armature|"), a Mixamo or Biped prefix ("mixamorig_", "bip01 ") or a
// Blender layer prefix (DEF- deform bones before plain names before ORG- before MCH-).
std::pair<std::string, int> matched_name(std::string_view raw) {
  std::string name = lowercase(raw);
  if (const auto cut = name.find_last_of(":|"); cut != std::string::npos) name.erase(0, cut + 1);
  for (const std::string_view prefix : {"mixamorig", "bip"}) {
    if (!name.starts_with(prefix)) continue;
    const std::size_t end = name.find_first_of("_ ", prefix.size());
    if (end != std::string::npos &&
        (end == prefix.size() ||
         is_digits(std::string_view(name).substr(prefix.size(), end - prefix.size()))))
      name.erase(0, end + 1);
  }
  constexpr std::string_view kLayers[] = {"def-", "", "org-", "mch-"};
  for (int rank = 0; rank < 4; ++rank)
    if (!kLayers[rank].empty() && name.starts_with(kLayers[rank]))
      return {name.substr(kLayers[rank].size()), rank};
  return {name, 1};
}

// The name without a numbered suffix (".001") or an "_end"/".end" suffix; "" when it has none.
std::string without_suffix(const std::string& name) {
  for (const std::string_view end : {"_end", ".end"})
    if (name.size() > end.size() && name.ends_with(end))
      return name.substr(0, name.size() - end.size());
  const auto dot = name.find_last_of('.');
  if (dot != std::string::npos && dot > 0 && is_digits(std::string_view(name).substr(dot + 1)))
    return name.substr(0, dot);
  return {};
}

// Joint names as matched (matched_name), each to the joint of the most preferred layer; names
// without their suffix apart, consulted only when no joint has the exact name.
class JointNameIndex {
 public:
  explicit JointNameIndex(const Skeleton& skeleton) {
    for (int j = 0; j < skeleton.size(); ++j) {
      const auto [name, layer] = matched_name(skeleton.joints[j].name);
      add(exact_, name, {j, layer});
      if (std::string bare = without_suffix(name); !bare.empty()) add(suffixed_, bare, {j, layer});
    }
  }
  // The first joint matching a pattern, '*' replaced by `side`; -1 when none does.
  int find(const Patterns& patterns, std::string_view side = {}) const {
    for (std::string_view pattern : patterns) {
      std::string name = lowercase(pattern);
      if (const auto star = name.find('*'); star != std::string::npos)
        name.replace(star, 1, lowercase(side));
      if (auto it = exact_.find(name); it != exact_.end()) return it->second.joint;
      if (auto it = suffixed_.find(name); it != suffixed_.end()) return it->second.joint;
    }
    return -1;
  }

 private:
  struct Entry {
    int joint;
    int layer;
  };
  static void add(std::unordered_map<std::string, Entry>& index, const std::string& name,
                  Entry entry) {
    auto [it, inserted] = index.try_emplace(name, entry);
    if (!inserted && entry.layer < it->second.layer) it->second = entry;
  }
  std::unordered_map<std::string, Entry> exact_, suffixed_;
};

// Finds a role on one side, trying each of the convention's side spellings.
int find_sided(const JointNameIndex& names, const NamingConvention& convention,
               const Patterns& patterns, bool left) {
  for (const SideSpelling& side : convention.sides)
    if (int j = names.find(patterns, left ? side.left : side.right); j >= 0) return j;
  return -1;
}

// Keeps `optional` only where it lies strictly above (`above`) or below `anchor`.
int keep_if_in_order(const Skeleton& skeleton, int optional, int anchor, bool above) {
  if (optional < 0) return -1;
  const bool fits = above ? is_strict_ancestor(skeleton, optional, anchor)
                          : is_strict_ancestor(skeleton, anchor, optional);
  return fits ? optional : -1;
}

// Why the required roles (upper, lower, end) do not make a limb below the pelvis; "" if they do.
std::string limb_problem(const Skeleton& skeleton, int pelvis, int upper, int lower, int end) {
  if (upper < 0 || lower < 0 || end < 0) return "missing";
  auto quoted = [&](int j) { return "'" + skeleton.joints[j].name + "'"; };
  if (!is_strict_ancestor(skeleton, upper, lower))
    return quoted(lower) + " is not below " + quoted(upper);
  if (!is_strict_ancestor(skeleton, lower, end))
    return quoted(end) + " is not below " + quoted(lower);
  if (pelvis >= 0 && !is_strict_ancestor(skeleton, pelvis, upper))
    return quoted(upper) + " is not below the pelvis " + quoted(pelvis);
  return {};
}

// The parent of `upper` when it hangs between the torso and this limb only: no other limb root
// and not the head below it, and not the pelvis. -1 otherwise.
int link_above(const Skeleton& skeleton, int upper, int pelvis, const std::vector<int>& others) {
  const int parent = skeleton.joints[upper].parent;
  if (parent < 0 || parent == pelvis) return -1;
  for (int other : others)
    if (other >= 0 && (other == parent || is_strict_ancestor(skeleton, parent, other))) return -1;
  return parent;
}

struct ConventionMatch {
  NamedRigParts parts;
  int roles_found = 0;
  int parts_named() const {
    return static_cast<int>(std::count(parts.problem.begin(), parts.problem.end(), ""));
  }
};

// "LeftArm/LeftForeArm/LeftHand, upperarm_l/lowerarm_l/hand_l, ..." over all conventions.
std::string expected_names(RigPart part) {
  std::vector<std::string> examples;
  for (const NamingConvention& c : naming_conventions()) {
    const bool left = part == RigPart::kLeftArm || part == RigPart::kLeftLeg;
    const std::string_view side = left ? c.sides[0].left : c.sides[0].right;
    std::vector<const Patterns*> roles;
    if (part == RigPart::kTorso) roles = {&c.pelvis};
    if (part == RigPart::kHead) roles = {&c.head};
    if (part == RigPart::kLeftArm || part == RigPart::kRightArm)
      roles = {&c.upper_arm, &c.forearm, &c.hand};
    if (part == RigPart::kLeftLeg || part == RigPart::kRightLeg)
      roles = {&c.thigh, &c.shin, &c.foot};
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

std::string missing_part(RigPart part) {
  const bool single = part == RigPart::kTorso || part == RigPart::kHead;
  return std::string("no ") + (part == RigPart::kTorso ? "pelvis" : to_string(part)) +
         ": expected " + (single ? "a joint like " : "joints like ") + expected_names(part);
}

ConventionMatch match_convention(const JointNameIndex& names, const Skeleton& skeleton,
                                 const NamingConvention& convention) {
  ConventionMatch match;
  NamedRigParts& parts = match.parts;
  RigMap& map = parts.map;
  parts.convention = convention.name;
  auto count = [&](int j) {
    match.roles_found += j >= 0;
    return j;
  };
  parts.pelvis = count(names.find(convention.pelvis));
  if (parts.pelvis >= 0 &&
      lowercase(skeleton.joints[parts.pelvis].name).find(convention.pelvis_marker) ==
          std::string::npos)
    parts.pelvis = -1;
  map.neck.head = count(names.find(convention.head));
  if (parts.pelvis < 0)
    parts.problem[static_cast<int>(RigPart::kTorso)] = missing_part(RigPart::kTorso);
  if (map.neck.head < 0)
    parts.problem[static_cast<int>(RigPart::kHead)] = missing_part(RigPart::kHead);
  for (const bool left : {true, false}) {
    auto sided = [&](const Patterns& patterns) {
      return count(find_sided(names, convention, patterns, left));
    };
    ArmJoints arm{sided(convention.clavicle), sided(convention.upper_arm),
                  sided(convention.forearm), sided(convention.hand)};
    const RigPart arm_part = left ? RigPart::kLeftArm : RigPart::kRightArm;
    if (std::string why = limb_problem(skeleton, parts.pelvis, arm.upper, arm.lower, arm.hand);
        why.empty()) {
      arm.clavicle = keep_if_in_order(skeleton, arm.clavicle, arm.upper, true);
      (left ? map.left_arm : map.right_arm) = arm;
    } else {
      parts.problem[static_cast<int>(arm_part)] =
          why == "missing" ? missing_part(arm_part) : std::string(to_string(arm_part)) + ": " + why;
    }
    LegJoints leg{sided(convention.hip), sided(convention.thigh), sided(convention.shin),
                  sided(convention.foot), sided(convention.toe)};
    const RigPart leg_part = left ? RigPart::kLeftLeg : RigPart::kRightLeg;
    if (std::string why = limb_problem(skeleton, parts.pelvis, leg.upper, leg.lower, leg.foot);
        why.empty()) {
      leg.hip = keep_if_in_order(skeleton, leg.hip, leg.upper, true);
      leg.toe = keep_if_in_order(skeleton, leg.toe, leg.foot, false);
      (left ? map.left_leg : map.right_leg) = leg;
    } else {
      parts.problem[static_cast<int>(leg_part)] =
          why == "missing" ? missing_part(leg_part) : std::string(to_string(leg_part)) + ": " + why;
    }
  }
  // Hip links and clavicles the names left out, from the hierarchy.
  const std::vector<int> limb_roots = {map.left_arm.upper, map.right_arm.upper, map.left_leg.upper,
                                       map.right_leg.upper, map.neck.head};
  auto others = [&](int upper) {
    std::vector<int> rest;
    for (int j : limb_roots)
      if (j != upper) rest.push_back(j);
    return rest;
  };
  for (ArmJoints* arm : {&map.left_arm, &map.right_arm})
    if (arm->upper >= 0 && arm->clavicle < 0)
      arm->clavicle = link_above(skeleton, arm->upper, parts.pelvis, others(arm->upper));
  for (LegJoints* leg : {&map.left_leg, &map.right_leg})
    if (leg->upper >= 0 && leg->hip < 0)
      leg->hip = link_above(skeleton, leg->upper, parts.pelvis, others(leg->upper));
  return match;
}

// The roles one convention gives the joints of `names` by name alone (rig_roles' order).
std::array<int, kRigRoleCount> convention_roles(const JointNameIndex& names,
                                                const NamingConvention& convention) {
  std::array<int, kRigRoleCount> roles;
  roles.fill(-1);
  int next = 0;
  roles[next++] = names.find(convention.pelvis);
  roles[next++] = names.find(convention.head);
  for (const bool left : {true, false}) {
    for (const Patterns* arm :
         {&convention.clavicle, &convention.upper_arm, &convention.forearm, &convention.hand})
      roles[next++] = find_sided(names, convention, *arm, left);
    for (const Patterns* leg :
         {&convention.hip, &convention.thigh, &convention.shin, &convention.foot, &convention.toe})
      roles[next++] = find_sided(names, convention, *leg, left);
  }
  return roles;
}

}  // namespace

std::array<int, kRigRoleCount> rig_roles(const RigMap& map) {
  std::array<int, kRigRoleCount> roles;
  int next = 0;
  roles[next++] = map.torso.pelvis();
  roles[next++] = map.neck.head;
  for (const bool left : {true, false}) {
    const ArmJoints& arm = left ? map.left_arm : map.right_arm;
    for (const int j : {arm.clavicle, arm.upper, arm.lower, arm.hand}) roles[next++] = j;
    const LegJoints& leg = left ? map.left_leg : map.right_leg;
    for (const int j : {leg.hip, leg.upper, leg.lower, leg.foot, leg.toe}) roles[next++] = j;
  }
  return roles;
}

NameRoles match_name_roles(std::span<const std::string> names) {
  Skeleton flat;  // the names as roots: JointNameIndex reads names only
  for (const std::string& name : names) flat.joints.push_back({.name = name});
  const JointNameIndex index(flat);
  NameRoles best{"", {}};
  best.roles.fill(-1);
  int best_count = 0;
  for (const NamingConvention& convention : naming_conventions()) {
    const std::array<int, kRigRoleCount> roles = convention_roles(index, convention);
    const int count =
        static_cast<int>(std::count_if(roles.begin(), roles.end(), [](int j) { return j >= 0; }));
    if (count > best_count) best = {std::string(convention.name), roles}, best_count = count;
  }
  return best;
}

bool NamedRigParts::settles_every_part() const {
  return std::all_of(problem.begin(), problem.end(),
                     [](const std::string& p) { return p.empty(); });
}

NamedRigParts match_rig_naming(const Skeleton& skeleton) {
  const JointNameIndex names(skeleton);
  std::optional<ConventionMatch> best;
  for (const NamingConvention& convention : naming_conventions()) {
    ConventionMatch match = match_convention(names, skeleton, convention);
    if (!best || match.parts_named() > best->parts_named() ||
        (match.parts_named() == best->parts_named() && match.roles_found > best->roles_found))
      best = std::move(match);
  }
  if (best->roles_found == 0) {  // not one name of a known convention
    std::string conventions;
    for (const NamingConvention& c : naming_conventions())
      if (conventions.find(c.name) == std::string::npos)
        conventions += (conventions.empty() ? "" : ", ") + std::string(c.name);
    best->parts.convention.clear();
    best->parts.problem.fill("no joint has a name of a known convention (" + conventions + ")");
  }
  return std::move(best->parts);
}

}  // namespace sweepd::deform
