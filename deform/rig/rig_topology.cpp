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

// Walks down single-child links from `start` to the first joint with three or more children.
int first_three_way_branch(const RestHierarchy& h, const Skeleton& skeleton, int start,
                           const std::string& what) {
  int j = start;
  while (h.children[j].size() == 1) j = h.children[j][0];
  if (h.children[j].size() < 3)
    throw std::invalid_argument("found no joint where " + what + " branch off: below " +
                                name(skeleton, start) + " the first branching joint " +
                                name(skeleton, j) + " has " + std::to_string(h.children[j].size()) +
                                " children, expected 3");
  return j;
}

std::vector<int> longest_path(const RestHierarchy& h, int start) {
  std::vector<int> path;
  for (int j = start; j >= 0; j = h.next_on_reach[j]) path.push_back(j);
  return path;
}

// The children of `joint` other than `excluded`, furthest-reaching first; at least two.
std::vector<int> two_longest_branches(const RestHierarchy& h, const Skeleton& skeleton, int joint,
                                      int excluded, const std::string& what) {
  std::vector<int> branches;
  for (int c : h.children[joint])
    if (c != excluded) branches.push_back(c);
  auto reach_from_joint = [&](int c) {
    return glm::distance(h.position[joint], h.position[c]) + h.reach[c];
  };
  std::sort(branches.begin(), branches.end(),
            [&](int a, int b) { return reach_from_joint(a) > reach_from_joint(b); });
  if (branches.size() < 2)
    throw std::invalid_argument("joint " + name(skeleton, joint) + " has fewer than two " + what +
                                " branches");
  branches.resize(2);
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

// True when joint a lies on the character's left of joint b.
bool is_left_of(const RestHierarchy& h, const Skeleton& skeleton, int a, int b,
                const glm::vec3& left) {
  const float side = glm::dot(h.position[a] - h.position[b], left);
  const float spread = glm::distance(h.position[a], h.position[b]);
  if (!(std::abs(side) > 0.1f * spread))
    throw std::invalid_argument("cannot tell left from right: " + name(skeleton, a) + " and " +
                                name(skeleton, b) + " are not side by side");
  return side > 0.0f;
}

}  // namespace

RigMap detect_rig_map_by_topology(const Skeleton& skeleton) {
  if (skeleton.size() == 0) throw std::invalid_argument("the skeleton has no joints");
  const RestHierarchy h = analyse(skeleton);
  int root = -1;
  for (int j = 0; j < skeleton.size(); ++j)
    if (skeleton.joints[j].parent < 0 && (root < 0 || h.subtree_size[j] > h.subtree_size[root]))
      root = j;

  const int pelvis = first_three_way_branch(h, skeleton, root, "the legs and the spine");
  int spine = -1;
  for (int c : h.children[pelvis])
    if (spine < 0 || h.subtree_size[c] > h.subtree_size[spine]) spine = c;
  const int chest = first_three_way_branch(h, skeleton, spine, "the arms and the neck");
  const glm::vec3 up_vector = h.position[chest] - h.position[pelvis];
  if (!(glm::length(up_vector) > 0.0f))
    throw std::invalid_argument("the chest " + name(skeleton, chest) + " sits on the pelvis " +
                                name(skeleton, pelvis));
  const glm::vec3 up = glm::normalize(up_vector);

  int neck = -1;
  float neck_upness = -2.0f;
  for (int c : h.children[chest]) {
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
  map.torso.chain = path_down(skeleton, pelvis, chest);
  for (int j : longest_path(h, neck)) {
    map.neck.chain.push_back(j);
    if (h.children[j].size() != 1) break;
  }
  map.neck.head = map.neck.chain.back();

  const std::vector<int> leg_starts = two_longest_branches(h, skeleton, pelvis, spine, "leg");
  LegJoints leg_a = leg_roles(h, skeleton, leg_starts[0]);
  LegJoints leg_b = leg_roles(h, skeleton, leg_starts[1]);
  for (const LegJoints* leg : {&leg_a, &leg_b})
    if (!(glm::dot(h.position[leg->foot] - h.position[pelvis], up) < 0.0f))
      throw std::invalid_argument("the leg ending at " + name(skeleton, leg->foot) +
                                  " does not reach below the pelvis " + name(skeleton, pelvis));
  const std::vector<int> arm_starts = two_longest_branches(h, skeleton, chest, neck, "arm");
  ArmJoints arm_a = arm_roles(h, skeleton, arm_starts[0]);
  ArmJoints arm_b = arm_roles(h, skeleton, arm_starts[1]);

  const glm::vec3 left = glm::cross(up, forward_direction(h, up, leg_a, leg_b));
  const bool leg_a_left = is_left_of(h, skeleton, leg_a.upper, leg_b.upper, left);
  map.left_leg = leg_a_left ? leg_a : leg_b;
  map.right_leg = leg_a_left ? leg_b : leg_a;
  const bool arm_a_left = is_left_of(h, skeleton, arm_a.upper, arm_b.upper, left);
  map.left_arm = arm_a_left ? arm_a : arm_b;
  map.right_arm = arm_a_left ? arm_b : arm_a;
  return map;
}

}  // namespace sweepd::deform
