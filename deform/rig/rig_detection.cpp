// detect_rig_map (declared in rig_map.h): names first, then the skeleton's shape part by part,
// then the torso and neck chains from the parts found.
#include <algorithm>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "deform/model/joint_paths.h"
#include "deform/rig/rig_map.h"
#include "deform/rig/rig_naming.h"
#include "deform/rig/rig_topology.h"

namespace sweepd::deform {

namespace {

int index_of(RigPart part) { return static_cast<int>(part); }

bool uses_any(const std::vector<int>& chain, const std::vector<int>& used) {
  return std::any_of(chain.begin(), chain.end(), [&](int j) {
    return j >= 0 && std::find(used.begin(), used.end(), j) != used.end();
  });
}

// The named parts, and for each part the names did not settle, the shape's part where it uses
// no joint a named part uses; the rest absent. Chains are not filled.
RigMap merge_parts(const NamedRigParts& named, const RigMap* shape) {
  RigMap map = named.map;
  map.convention = named.convention.empty() ? "topological" : named.convention;
  std::vector<int> used = {named.pelvis, map.neck.head};
  for (const std::vector<int>& chain :
       {map.left_arm.chain(), map.right_arm.chain(), map.left_leg.chain(), map.right_leg.chain()})
    used.insert(used.end(), chain.begin(), chain.end());
  auto settle = [&](RigPart part, bool shape_has_it, const std::vector<int>& shape_joints,
                    auto assign) {
    const std::string& why = named.problem[index_of(part)];
    PartDetection& found = map.found[index_of(part)];
    if (why.empty()) {
      found = {PartFinding::kByName, ""};
    } else if (shape_has_it && !uses_any(shape_joints, used)) {
      assign();
      found = {PartFinding::kByShape, why};
    } else {
      const std::string shape_note = shape ? shape->found[index_of(part)].note : "";
      found = {PartFinding::kAbsent, why + (shape_note.empty() ? "" : "; shape: " + shape_note)};
    }
  };
  const RigMap none;
  const RigMap& s = shape ? *shape : none;
  settle(RigPart::kTorso, s.torso.chain.size() >= 2, {}, [] {});
  settle(RigPart::kHead, s.has_head(), {s.neck.head}, [&] { map.neck.head = s.neck.head; });
  settle(RigPart::kLeftArm, !s.left_arm.absent(), s.left_arm.chain(),
         [&] { map.left_arm = s.left_arm; });
  settle(RigPart::kRightArm, !s.right_arm.absent(), s.right_arm.chain(),
         [&] { map.right_arm = s.right_arm; });
  settle(RigPart::kLeftLeg, !s.left_leg.absent(), s.left_leg.chain(),
         [&] { map.left_leg = s.left_leg; });
  settle(RigPart::kRightLeg, !s.right_leg.absent(), s.right_leg.chain(),
         [&] { map.right_leg = s.right_leg; });
  return map;
}

// Fills the torso (pelvis up to the chest, the deepest common ancestor of the arms and the
// head; `fallback_chest` where fewer than two of them are present) and the neck (below the
// chest down to the head). Returns the problem, or "".
std::string complete_chains(RigMap& map, int pelvis, int fallback_chest, const Skeleton& skeleton) {
  std::vector<int> anchors;
  for (const ArmJoints* arm : {&map.left_arm, &map.right_arm})
    if (!arm->absent()) anchors.push_back(arm->clavicle >= 0 ? arm->clavicle : arm->upper);
  if (map.has_head()) anchors.push_back(map.neck.head);
  int chest = fallback_chest;
  if (anchors.size() >= 2) {
    chest = anchors[0];
    for (int j : anchors) chest = common_ancestor(skeleton, chest, j);
  }
  if (chest < 0) return "found no chest: fewer than two of the arms and the head";
  map.torso.chain = path_down(skeleton, pelvis, chest);
  if (map.torso.chain.size() < 2)
    return "the arms and the head do not meet above the pelvis '" + skeleton.joints[pelvis].name +
           "'";
  map.neck.chain.clear();
  if (map.has_head()) {
    if (chest == map.neck.head)
      return "the arms hang below the head '" + skeleton.joints[map.neck.head].name + "'";
    map.neck.chain = path_down(skeleton, chest, map.neck.head);
    if (!map.neck.chain.empty()) map.neck.chain.erase(map.neck.chain.begin());
  }
  return validate_rig_map(map, skeleton);
}

void add_absent_part_warnings(RigMap& map) {
  auto absent = [&](RigPart part) {
    return map.found[index_of(part)].finding == PartFinding::kAbsent;
  };
  auto why = [&](RigPart part) { return " (" + map.found[index_of(part)].note + ")"; };
  if (absent(RigPart::kHead))
    map.warnings.push_back("no head found: the neck and head are skinned by linear blending" +
                           why(RigPart::kHead));
  const struct {
    RigPart left, right;
    const char* both;
  } pairs[] = {{RigPart::kLeftArm, RigPart::kRightArm, "arms"},
               {RigPart::kLeftLeg, RigPart::kRightLeg, "legs"}};
  for (const auto& pair : pairs) {
    if (absent(pair.left) && absent(pair.right)) {
      map.warnings.push_back(std::string("no ") + pair.both + " found: " + pair.both +
                             " are skinned by linear blending" + why(pair.left));
      continue;
    }
    for (RigPart part : {pair.left, pair.right})
      if (absent(part))
        map.warnings.push_back(std::string("no ") + to_string(part) + " found: the " +
                               to_string(part) + " is skinned by linear blending" + why(part));
  }
}

// Parts the map has but the binding cannot sweep (bind.cpp, plan_sweeps): a neck of one joint,
// or a torso of one joint with no neck above it, has no link to sweep along; an arm without a
// hand joint has no forearm link.
void add_unswept_part_warnings(RigMap& map, const Skeleton& skeleton) {
  auto joint = [&](int j) { return "'" + skeleton.joints[j].name + "'"; };
  if (map.torso_sweep_chain().size() == 1)
    map.warnings.push_back("the torso is one joint (" + joint(map.torso.pelvis()) +
                           ") with no neck above it: with no link to sweep along it is skinned by "
                           "linear blending; the limbs are swept up to it");
  if (map.has_head() && map.neck.chain.size() == 1)
    map.warnings.push_back("the neck is one joint (" + joint(map.neck.head) +
                           ", the head's): the neck and head are skinned by linear blending");
  for (const auto& [arm, side] :
       {std::pair{&map.left_arm, "left"}, std::pair{&map.right_arm, "right"}})
    if (!arm->absent() && arm->hand < 0)
      map.warnings.push_back(std::string("the ") + side + " arm has no hand joint (its forearm " +
                             joint(arm->lower) + " carries the hand): the " + side +
                             " forearm is skinned by linear blending from the elbow on");
}

// Side names are trusted for the facing (rest_body_axes: left is where the joints named left
// are), so a rig whose names put its left side on its right is read facing backwards and plays
// every clip turned around. The toes say which way the body faces whatever the names are: where
// they point against the facing the names give, say so.
void add_side_names_warning(RigMap& map, const Skeleton& skeleton) {
  const LegJoints& a = map.left_leg;
  const LegJoints& b = map.right_leg;
  const bool sides_from_names =
      map.found[index_of(RigPart::kLeftArm)].finding == PartFinding::kByName ||
      map.found[index_of(RigPart::kLeftLeg)].finding == PartFinding::kByName;
  if (!sides_from_names) return;
  const std::vector<glm::mat4> world_rest = skeleton.world_rest_matrices();
  const BodyAxes axes = rest_body_axes(map, world_rest);
  std::vector<glm::vec3> positions;
  for (const glm::mat4& m : world_rest) positions.emplace_back(m[3]);
  const std::optional<glm::vec3> toes = toes_forward(positions, axes.up, a, b);
  // Pointing more than 120° away from the named facing: not a splayed foot but a body turned
  // around.
  if (!toes || glm::dot(*toes, axes.forward) >= -0.5f) return;
  const glm::vec3 toward = *toes;
  auto vector = [](const glm::vec3& v) {
    char text[64];
    std::snprintf(text, sizeof text, "(%.2f, %.2f, %.2f)", v.x, v.y, v.z);
    return std::string(text);
  };
  map.warnings.push_back("the side names contradict the feet: the toes point " + vector(toward) +
                         ", so the joints named left ('" +
                         skeleton.joints[a.upper >= 0 ? a.upper : a.foot].name +
                         "') lie on the body's right; the names are followed and the body is "
                         "read facing " +
                         vector(axes.forward) +
                         ", so clips play turned around: swap its Left and Right names if the "
                         "toes are right");
}

void add_warnings(RigMap& map, const Skeleton& skeleton) {
  add_absent_part_warnings(map);
  add_unswept_part_warnings(map, skeleton);
  add_side_names_warning(map, skeleton);
}

}  // namespace

RigMap detect_rig_map(const Skeleton& skeleton) {
  if (std::string why = skeleton.validate(); !why.empty())
    throw std::invalid_argument("cannot map an invalid skeleton: " + why);
  const NamedRigParts named = match_rig_naming(skeleton);
  if (named.settles_every_part()) {
    RigMap map = merge_parts(named, nullptr);
    if (complete_chains(map, named.pelvis, -1, skeleton).empty()) {
      add_warnings(map, skeleton);
      return map;
    }
  }
  RigMap shape;
  std::string shape_problem;
  try {
    shape = detect_rig_map_by_topology(skeleton);
  } catch (const std::invalid_argument& e) {
    shape_problem = e.what();
  }
  const bool shape_found = shape_problem.empty();
  RigMap map = merge_parts(named, shape_found ? &shape : nullptr);
  const int pelvis = named.pelvis >= 0 ? named.pelvis : shape.torso.pelvis();
  std::string why =
      pelvis < 0 ? "no pelvis" : complete_chains(map, pelvis, shape.torso.chest(), skeleton);
  if (!why.empty() && shape_found && validate_rig_map(shape, skeleton).empty()) {
    map = std::move(shape);  // named and shape parts do not fit together: the shape alone does
    why.clear();
  }
  if (!why.empty()) {
    const std::string& names = named.problem[index_of(RigPart::kTorso)];
    throw std::invalid_argument(
        "cannot map the skeleton's joints: found no torso chain (" +
        (named.convention.empty() ? names : named.convention + " names: " + names) +
        (shape_found ? "); names and shape together: " + why
                     : "); and the topological fallback failed: " + shape_problem));
  }
  add_warnings(map, skeleton);
  return map;
}

}  // namespace sweepd::deform
