#include "deform/rig/rig_topology.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <span>
#include <stdexcept>
#include <vector>

#include "deform/model/joint_paths.h"

namespace sweepd::deform {

namespace {

// Joints are the skeleton's; a skeleton of several roots (glTF joints whose common parent node
// is not a joint, e.g. OpenPose's MidHip, LHip and RHip) gets one more node, `forest_root`,
// at its largest root, with the roots as children, so that its legs and spine branch there.
struct RestHierarchy {
  int forest_root = -1;                    // that extra node's index (== joint count), or -1
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
  std::vector<int> roots;
  for (int j = 0; j < n; ++j)
    if (skeleton.joints[j].parent < 0) roots.push_back(j);
  if (roots.size() > 1) {
    h.forest_root = n;
    h.children.push_back(roots);
    h.subtree_size.push_back(1);
    h.reach.push_back(0.0f);
    h.next_on_reach.push_back(-1);
  }
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
  if (h.forest_root >= 0) {
    int largest = roots[0];
    for (int r : roots)
      if (h.subtree_size[r] > h.subtree_size[largest]) largest = r;
    h.position.push_back(h.position[largest]);
    for (int r : roots) {
      h.subtree_size[n] += h.subtree_size[r];
      const float through_r = glm::distance(h.position[n], h.position[r]) + h.reach[r];
      if (h.next_on_reach[n] < 0 || through_r > h.reach[n]) {
        h.reach[n] = through_r;
        h.next_on_reach[n] = r;
      }
    }
  }
  return h;
}

// The joints from the hierarchy node `top` (a joint or the forest root) down to `joint`.
std::vector<int> path_down_from(const RestHierarchy& h, const Skeleton& skeleton, int top,
                                int joint) {
  if (top != h.forest_root) return path_down(skeleton, top, joint);
  int root = joint;
  while (skeleton.joints[root].parent >= 0) root = skeleton.joints[root].parent;
  return path_down(skeleton, root, joint);
}

std::string name(const Skeleton& skeleton, int j) {
  return j < skeleton.size() ? "'" + skeleton.joints[j].name + "'" : "the skeleton's roots";
}

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

// The children of `joint` not in `excluded`, furthest-reaching first; at most two.
std::vector<int> two_longest_branches(const RestHierarchy& h, int joint,
                                      const std::vector<int>& excluded) {
  std::vector<int> branches;
  for (int c : h.children[joint])
    if (std::find(excluded.begin(), excluded.end(), c) == excluded.end()) branches.push_back(c);
  auto reach_from_joint = [&](int c) {
    return glm::distance(h.position[joint], h.position[c]) + h.reach[c];
  };
  std::sort(branches.begin(), branches.end(),
            [&](int a, int b) { return reach_from_joint(a) > reach_from_joint(b); });
  if (branches.size() > 2) branches.resize(2);
  return branches;
}

// Where the path from `joint` through child `c` ends, relative to `joint`.
glm::vec3 reach_of(const RestHierarchy& h, int joint, int c) {
  return h.position[longest_path(h, c).back()] - h.position[joint];
}

// Legs agree on where they reach: within about 45° of each other.
constexpr float kLegsAgree = 0.7f;

// A one-joint torso: the legs, arms and neck all branch from `joint` (low-poly game rigs). Its
// legs are the two children reaching furthest in agreeing directions, provided two more
// children (the arms) are left; empty otherwise.
std::vector<int> legs_beside_arms(const RestHierarchy& h, int joint) {
  const std::vector<int>& children = h.children[joint];
  if (children.size() < 4) return {};
  std::vector<int> best;
  float best_reach = 0.0f;
  for (std::size_t a = 0; a < children.size(); ++a)
    for (std::size_t b = a + 1; b < children.size(); ++b) {
      const glm::vec3 ra = reach_of(h, joint, children[a]), rb = reach_of(h, joint, children[b]);
      const float shorter = std::min(glm::length(ra), glm::length(rb));
      if (!(shorter > 0.0f) || glm::dot(ra, rb) < kLegsAgree * glm::length(ra) * glm::length(rb))
        continue;
      if (shorter > best_reach) {
        best_reach = shorter;
        best = {children[a], children[b]};
      }
    }
  // The legs reach furthest of all the children: arms hanging beside each other do not.
  for (int c : children)
    if (!best.empty() && c != best[0] && c != best[1] &&
        glm::length(reach_of(h, joint, c)) > best_reach)
      return {};
  return best;
}

// The mean rest position of the joints below `joint` (itself excluded), leaving out the
// subtrees of `excluded` children.
glm::vec3 mean_below(const RestHierarchy& h, int joint, const std::vector<int>& excluded) {
  glm::vec3 sum(0.0f);
  int count = 0;
  std::vector<int> open;
  for (int c : h.children[joint])
    if (std::find(excluded.begin(), excluded.end(), c) == excluded.end()) open.push_back(c);
  while (!open.empty()) {
    const int j = open.back();
    open.pop_back();
    sum += h.position[j];
    ++count;
    open.insert(open.end(), h.children[j].begin(), h.children[j].end());
  }
  return count > 0 ? sum / static_cast<float>(count) : h.position[joint];
}

// Up, from the pelvis to the chest. Where the two coincide (a one-joint torso, or OpenPose's
// MidHip at the roots): towards the mean of the joints above the chest (neck, head and arms:
// the legs' reach leans with the feet), else away from where the legs reach. Zero when nothing
// tells.
glm::vec3 torso_up(const RestHierarchy& h, int pelvis, int chest,
                   const std::vector<int>& leg_starts) {
  const glm::vec3 spine = h.position[chest] - h.position[pelvis];
  if (glm::length(spine) > 1e-4f) return glm::normalize(spine);
  glm::vec3 up = mean_below(h, chest, leg_starts) - h.position[chest];
  if (!(glm::length(up) > 1e-4f))
    for (int leg : leg_starts) up -= glm::normalize(reach_of(h, pelvis, leg));
  return glm::length(up) > 1e-4f ? glm::normalize(up) : glm::vec3(0.0f);
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

// A joint this close to the torso's centre line, relative to the arm's length, is no shoulder.
constexpr float kOnTheCentreLine = 0.15f;

// `chest` and `up` give the torso's centre line. An arm of three joints whose first sits on it
// (OpenPose's LShoulder starts at the neck) is clavicle, upper arm and a forearm that ends in no
// joint (hand -1: the hand rides on the forearm's joint).
ArmJoints arm_roles(const RestHierarchy& h, const Skeleton& skeleton, int start,
                    const glm::vec3& chest, const glm::vec3& up) {
  const std::vector<int> path = longest_path(h, start);
  if (path.size() == 3) {
    const glm::vec3 from_chest = h.position[path[0]] - chest;
    const float off_centre = glm::length(from_chest - glm::dot(from_chest, up) * up);
    const float length = glm::distance(h.position[path[0]], h.position[path[1]]) +
                         glm::distance(h.position[path[1]], h.position[path[2]]);
    if (off_centre < kOnTheCentreLine * length) return {path[0], path[1], path[2], -1};
  }
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

}  // namespace

std::optional<glm::vec3> toes_forward(std::span<const glm::vec3> joint_positions,
                                      const glm::vec3& up, const LegJoints& a, const LegJoints& b) {
  if (a.toe < 0 || b.toe < 0 || a.foot < 0 || b.foot < 0) return std::nullopt;
  glm::vec3 toes(0.0f);
  float length = 0.0f;
  for (const LegJoints* leg : {&a, &b}) {
    const glm::vec3 foot = joint_positions[leg->toe] - joint_positions[leg->foot];
    toes += horizontal(foot, up);
    length += glm::length(foot);
  }
  // Toes that agree on a mostly horizontal direction tell the facing.
  if (glm::length(toes) > 0.3f * length) return glm::normalize(toes);
  return std::nullopt;
}

namespace {

// The direction the body faces: where the toes point, else the glTF convention.
glm::vec3 forward_direction(const RestHierarchy& h, const glm::vec3& up, const LegJoints& a,
                            const LegJoints& b) {
  if (const std::optional<glm::vec3> toes = toes_forward(h.position, up, a, b)) return *toes;
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
  // The roots together (OpenPose's legs and spine); where they do not branch there, the body is
  // under the largest root and the others are props.
  int largest_root = -1;
  for (int j = 0; j < skeleton.size(); ++j)
    if (skeleton.joints[j].parent < 0 &&
        (largest_root < 0 || h.subtree_size[j] > h.subtree_size[largest_root]))
      largest_root = j;
  int root = h.forest_root >= 0 && first_branch_of(h, h.forest_root, 3) >= 0 ? h.forest_root
                                                                             : largest_root;
  const int first_branch = first_branch_of(h, root, 3);
  if (first_branch < 0)
    throw std::invalid_argument(
        "found no joint where the legs and the spine (or the arms and the neck) branch off: "
        "below " +
        name(skeleton, root) + " no joint has 3 or more children");
  std::vector<int> leg_starts = legs_beside_arms(h, first_branch);
  int spine = -1;
  for (int c : h.children[first_branch])
    if (leg_starts.empty() && (spine < 0 || h.subtree_size[c] > h.subtree_size[spine])) spine = c;
  // With legs: the first branch is the pelvis and the spine branches again at the chest (three
  // ways: neck and arms; two ways: arms only, a body without a head), and the two other chains
  // at the pelvis reach below it. Else (a bust, a seated avatar cut at the waist) the first
  // branch is the chest and the torso runs up to it from the root.
  int pelvis = first_branch;
  int chest = leg_starts.empty() ? first_branch_of(h, spine, 2) : first_branch;
  std::string legs_note;
  if (chest >= 0 && leg_starts.empty()) {
    const glm::vec3 up = torso_up(h, pelvis, chest, {});
    for (int start : two_longest_branches(h, pelvis, {spine})) {
      const glm::vec3 reach = reach_of(h, pelvis, start);
      if (glm::dot(reach, up) < -kLegsAgainstSpine * glm::length(reach))
        leg_starts.push_back(start);
    }
  }
  if (leg_starts.size() < 2) {
    leg_starts.clear();
    legs_note = chest < 0 ? "the spine does not branch again above " + name(skeleton, first_branch)
                          : "no chain below " + name(skeleton, first_branch) + " reaches down";
    chest = first_branch;
    pelvis = root;  // the chest itself where it is the root: a bust's one-joint torso
  }
  const glm::vec3 up = torso_up(h, pelvis, chest, leg_starts);
  if (!(glm::length(up) > 0.0f))
    throw std::invalid_argument("found no torso chain: the chest " + name(skeleton, chest) +
                                " sits on the pelvis " + name(skeleton, pelvis) +
                                " and no legs tell which way is up");

  // The neck, unless only the arms branch off the chest (besides the legs of a one-joint torso).
  std::vector<int> upper_body;
  for (int c : h.children[chest])
    if (std::find(leg_starts.begin(), leg_starts.end(), c) == leg_starts.end())
      upper_body.push_back(c);
  int neck = -1;
  float neck_upness = -2.0f;
  const bool has_neck = upper_body.size() >= 3;
  for (int c : has_neck ? upper_body : std::vector<int>{}) {
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
  map.torso.chain = path_down_from(h, skeleton, pelvis, chest);
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
  std::vector<int> not_arms = leg_starts;
  not_arms.push_back(neck);
  for (int start : two_longest_branches(h, chest, not_arms)) {
    try {
      arms.push_back(arm_roles(h, skeleton, start, h.position[chest], up));
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
