#include "deform/rig/rig_topology.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "deform/model/joint_paths.h"

namespace sweepd::deform {

namespace {

struct RestHierarchy {
  std::vector<glm::vec3> position;         // world rest position per joint
  std::vector<std::vector<int>> children;  // per joint
  std::vector<int> subtree_size;           // joints in the subtree, itself included
  std::vector<float> reach;                // length of the longest path down to a leaf
  std::vector<int> next_on_reach;          // child on that path, -1 at a leaf
};

RestHierarchy analyse(const Skeleton& skeleton) {
  const int n = skeleton.size();
  RestHierarchy h;
  for (const glm::mat4& world : skeleton.world_rest_matrices())
    h.position.push_back(glm::vec3(world[3]));
  h.children.resize(n);
  for (int j = 0; j < n; ++j)
    if (skeleton.joints[j].parent >= 0) h.children[skeleton.joints[j].parent].push_back(j);
  h.subtree_size.assign(n, 1);
  h.reach.assign(n, 0.0f);
  h.next_on_reach.assign(n, -1);
  for (int j = n - 1; j >= 0; --j) {  // children before parents
    for (int c : h.children[j]) {
      h.subtree_size[j] += h.subtree_size[c];
      const float through_c = glm::distance(h.position[j], h.position[c]) + h.reach[c];
      if (h.next_on_reach[j] < 0 || through_c > h.reach[j]) {
        h.reach[j] = through_c;
        h.next_on_reach[j] = c;
      }
    }
  }
  return h;
}

std::string name(const Skeleton& skeleton, int j) { return "'" + skeleton.joints[j].name + "'"; }

// Legs point away from the spine: the line from the pelvis to each leg's end lies within 60° of
// the direction opposite the spine (cos 60° = 0.5). A neck and an arm hanging off a chest mistaken
// for a pelvis (legless bodies) do not both do so.
constexpr float kLegsAgainstSpine = 0.5f;

// Walks down single-child links from `start` to the first joint with `ways` or more children;
// -1 when the walk ends at a joint with fewer.
int first_branch_of(const RestHierarchy& h, int start, std::size_t ways) {
  int j = start;
  while (h.children[j].size() == 1) j = h.children[j][0];
  return h.children[j].size() >= ways ? j : -1;
}

std::vector<int> longest_path(const RestHierarchy& h, int start) {
  std::vector<int> path;
  for (int j = start; j >= 0; j = h.next_on_reach[j]) path.push_back(j);
  return path;
}

// The children of `joint` other than `excluded`, furthest-reaching first; at most two.
std::vector<int> two_longest_branches(const RestHierarchy& h, int joint, int excluded) {
  std::vector<int> branches;
  for (int c : h.children[joint])
    if (c != excluded) branches.push_back(c);
  auto reach_from_joint = [&](int c) {
    return glm::distance(h.position[joint], h.position[c]) + h.reach[c];
  };
  std::sort(branches.begin(), branches.end(),
            [&](int a, int b) { return reach_from_joint(a) > reach_from_joint(b); });
  if (branches.size() > 2) branches.resize(2);
  return branches;
}

// Index i along `path` where the segments i..i+1 and i+1..i+2 are longest together.
int longest_segment_pair(const RestHierarchy& h, const Skeleton& skeleton,
                         const std::vector<int>& path, const std::string& what) {
  if (path.size() < 3)
    throw std::invalid_argument("the " + what + " starting at " + name(skeleton, path[0]) +
                                " has " + std::to_string(path.size()) +
                                " joints, expected at least 3");
  int best = 0;
  float best_length = -1.0f;
  for (std::size_t i = 0; i + 2 < path.size(); ++i) {
    const float length = glm::distance(h.position[path[i]], h.position[path[i + 1]]) +
                         glm::distance(h.position[path[i + 1]], h.position[path[i + 2]]);
    if (length > best_length) {
      best_length = length;
      best = static_cast<int>(i);
    }
  }
  return best;
}

ArmJoints arm_roles(const RestHierarchy& h, const Skeleton& skeleton, int start) {
  const std::vector<int> path = longest_path(h, start);
  const int i = longest_segment_pair(h, skeleton, path, "arm");
  return {i > 0 ? path[i - 1] : -1, path[i], path[i + 1], path[i + 2]};
}

LegJoints leg_roles(const RestHierarchy& h, const Skeleton& skeleton, int start) {
  const std::vector<int> path = longest_path(h, start);
  const int i = longest_segment_pair(h, skeleton, path, "leg");
  const int toe = i + 3 < static_cast<int>(path.size()) ? path[i + 3] : -1;
  return {i > 0 ? path[i - 1] : -1, path[i], path[i + 1], path[i + 2], toe};
}

glm::vec3 horizontal(const glm::vec3& v, const glm::vec3& up) { return v - glm::dot(v, up) * up; }

// The direction the body faces: where the toes point, else the glTF convention.
glm::vec3 forward_direction(const RestHierarchy& h, const glm::vec3& up, const LegJoints& a,
                            const LegJoints& b) {
  if (a.toe >= 0 && b.toe >= 0) {
    glm::vec3 toes(0.0f);
    float length = 0.0f;
    for (const LegJoints* leg : {&a, &b}) {
      const glm::vec3 foot = h.position[leg->toe] - h.position[leg->foot];
      toes += horizontal(foot, up);
      length += glm::length(foot);
    }
    // Toes that agree on a mostly horizontal direction tell the facing.
    if (glm::length(toes) > 0.3f * length) return glm::normalize(toes);
  }
  const glm::vec3 z_forward = horizontal(glm::vec3(0, 0, 1), up);
  if (glm::length(z_forward) > 0.5f) return glm::normalize(z_forward);
  return glm::normalize(horizontal(glm::vec3(0, -1, 0), up));
}

// Which side each of up to two limbs is on: `sided[0]` left, `sided[1]` right, absent where a
// limb is missing or the sides cannot be told (then the note says why). `root` of a limb is
// its upper joint; a lone limb's side is read against `centre`.
template <typename Limb>
void assign_sides(const RestHierarchy& h, const Skeleton& skeleton, std::vector<Limb> limbs,
                  int centre, const glm::vec3& left, Limb& left_limb, Limb& right_limb,
                  std::string& left_note, std::string& right_note) {
  if (limbs.empty()) return;
  const int other = limbs.size() == 2 ? limbs[1].upper : centre;
  const glm::vec3 offset = h.position[limbs[0].upper] - h.position[other];
  const float side = glm::dot(offset, left);
  if (!(std::abs(side) > 0.1f * glm::length(offset))) {
    left_note = right_note = "cannot tell left from right: " + name(skeleton, limbs[0].upper) +
                             " and " + name(skeleton, other) + " are not side by side";
    return;
  }
  const bool first_left = side > 0.0f;
  (first_left ? left_limb : right_limb) = limbs[0];
  if (limbs.size() == 2) (first_left ? right_limb : left_limb) = limbs[1];
  std::string& lone = first_left ? right_note : left_note;
  if (limbs.size() == 1 && lone.empty()) lone = "only one limb hangs there";
}

}  // namespace

RigMap detect_rig_map_by_topology(const Skeleton& skeleton) {
  if (skeleton.size() == 0) throw std::invalid_argument("the skeleton has no joints");
  const RestHierarchy h = analyse(skeleton);
  int root = -1;
  for (int j = 0; j < skeleton.size(); ++j)
    if (skeleton.joints[j].parent < 0 && (root < 0 || h.subtree_size[j] > h.subtree_size[root]))
      root = j;

  const int first_branch = first_branch_of(h, root, 3);
  if (first_branch < 0)
    throw std::invalid_argument(
        "found no joint where the legs and the spine (or the arms and the neck) branch off: "
        "below " +
        name(skeleton, root) + " no joint has 3 or more children");
  int spine = -1;
  for (int c : h.children[first_branch])
    if (spine < 0 || h.subtree_size[c] > h.subtree_size[spine]) spine = c;
  // With legs: the first branch is the pelvis and the spine branches again at the chest (three
  // ways: neck and arms; two ways: arms only, a body without a head), and the two other chains
  // at the pelvis reach below it. Else (a bust, a seated avatar cut at the waist) the first
  // branch is the chest and the torso runs up to it from the root.
  int pelvis = first_branch;
  int chest = first_branch_of(h, spine, 2);
  std::vector<int> leg_starts;
  std::string legs_note;
  if (chest >= 0) {
    const glm::vec3 up = glm::normalize(h.position[chest] - h.position[pelvis]);
    for (int start : two_longest_branches(h, pelvis, spine)) {
      const glm::vec3 reach = h.position[longest_path(h, start).back()] - h.position[pelvis];
      if (glm::dot(reach, up) < -kLegsAgainstSpine * glm::length(reach))
        leg_starts.push_back(start);
    }
  }
  if (leg_starts.size() < 2) {
    leg_starts.clear();
    legs_note = chest < 0 ? "the spine does not branch again above " + name(skeleton, first_branch)
                          : "no chain below " + name(skeleton, first_branch) + " reaches down";
    chest = first_branch;
    pelvis = root;
    if (pelvis == chest)
      throw std::invalid_argument("found no torso chain: the joint " + name(skeleton, chest) +
                                  " where the arms and the neck branch off is the root, and "
                                  "no chains reach below it for legs");
  }
  const glm::vec3 up_vector = h.position[chest] - h.position[pelvis];
  if (!(glm::length(up_vector) > 0.0f))
    throw std::invalid_argument("found no torso chain: the chest " + name(skeleton, chest) +
                                " sits on the pelvis " + name(skeleton, pelvis));
  const glm::vec3 up = glm::normalize(up_vector);

  // The neck, unless only the arms branch off the chest.
  int neck = -1;
  float neck_upness = -2.0f;
  const bool has_neck = h.children[chest].size() >= 3;
  for (int c : has_neck ? h.children[chest] : std::vector<int>{}) {
    glm::vec3 mean(0.0f);
    const std::vector<int> path = longest_path(h, c);
    for (int j : path) mean += h.position[j] / static_cast<float>(path.size());
    const glm::vec3 offset = mean - h.position[chest];
    const float upness = glm::length(offset) > 0.0f ? glm::dot(glm::normalize(offset), up) : 0.0f;
    if (upness > neck_upness) {
      neck_upness = upness;
      neck = c;
    }
  }

  RigMap map;
  map.convention = "topological";
  for (PartDetection& found : map.found) found = {PartFinding::kByShape, ""};
  map.torso.chain = path_down(skeleton, pelvis, chest);
  if (has_neck) {
    for (int j : longest_path(h, neck)) {
      map.neck.chain.push_back(j);
      if (h.children[j].size() != 1) break;
    }
    map.neck.head = map.neck.chain.back();
  } else {
    map.found[static_cast<int>(RigPart::kHead)] = {
        PartFinding::kAbsent,
        "only two chains (the arms) branch off the chest " + name(skeleton, chest)};
  }

  std::vector<LegJoints> legs;
  for (int start : leg_starts) {
    try {
      legs.push_back(leg_roles(h, skeleton, start));
    } catch (const std::invalid_argument& e) {
      legs_note = e.what();
    }
  }
  std::vector<ArmJoints> arms;
  std::string arms_note =
      "no chains besides the neck branch off the chest " + name(skeleton, chest);
  for (int start : two_longest_branches(h, chest, neck)) {
    try {
      arms.push_back(arm_roles(h, skeleton, start));
    } catch (const std::invalid_argument& e) {
      arms_note = e.what();
    }
  }
  const LegJoints no_leg;
  const glm::vec3 left =
      glm::cross(up, forward_direction(h, up, legs.size() == 2 ? legs[0] : no_leg,
                                       legs.size() == 2 ? legs[1] : no_leg));
  std::string notes[kRigPartCount];
  assign_sides(h, skeleton, legs, pelvis, left, map.left_leg, map.right_leg,
               notes[static_cast<int>(RigPart::kLeftLeg)],
               notes[static_cast<int>(RigPart::kRightLeg)]);
  assign_sides(h, skeleton, arms, chest, left, map.left_arm, map.right_arm,
               notes[static_cast<int>(RigPart::kLeftArm)],
               notes[static_cast<int>(RigPart::kRightArm)]);
  const std::pair<RigPart, bool> limbs[] = {{RigPart::kLeftArm, map.left_arm.absent()},
                                            {RigPart::kRightArm, map.right_arm.absent()},
                                            {RigPart::kLeftLeg, map.left_leg.absent()},
                                            {RigPart::kRightLeg, map.right_leg.absent()}};
  for (const auto& [part, absent] : limbs) {
    if (!absent) continue;
    const int i = static_cast<int>(part);
    const bool arm = part == RigPart::kLeftArm || part == RigPart::kRightArm;
    map.found[i] = {PartFinding::kAbsent, !notes[i].empty() ? notes[i]
                                          : arm             ? arms_note
                                                            : legs_note};
  }
  return map;
}

}  // namespace sweepd::deform
