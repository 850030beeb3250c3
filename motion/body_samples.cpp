#include "motion/body_samples.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "deform/binding/bound_model.h"

namespace sweepd::motion {

namespace {

constexpr int kDirections = 64;
// A bent joint's skin sampled again in bands by the joint's share: its lowest point, bent, is
// where the two bones' skins meet (the kneecap), which is no part's furthest point at rest.
constexpr int kBendBands = 6;
// The mitre's stretch stops growing at a 120° bend (2x): it grows without bound as a joint
// folds shut, where the sweep's skin on the inside meets itself instead.
constexpr float kMitreCosHalfBendLimit = 0.5f;
// The binding's link keys per link: the sweep turns the skin from a bone's frame at its link key
// to the joint key's, half-way between the two bones, over that span.
const int kLinkKeysPerLink = deform::BindOptions{}.intermediate_keys_per_link;

// kDirections unit vectors spread evenly over the sphere (a Fibonacci lattice).
std::vector<glm::vec3> sphere_directions() {
  std::vector<glm::vec3> directions;
  const float golden = static_cast<float>(M_PI) * (3.0f - std::sqrt(5.0f));
  for (int i = 0; i < kDirections; ++i) {
    const float y = 1.0f - 2.0f * (static_cast<float>(i) + 0.5f) / kDirections;
    const float r = std::sqrt(std::max(0.0f, 1.0f - y * y));
    directions.emplace_back(r * std::cos(golden * i), y, r * std::sin(golden * i));
  }
  return directions;
}

// The joint a vertex's skin bends about: of its two strongest influences, the one whose parent
// is the other; -1 when they are not parent and child (or it has one influence), or when any
// influence is blended linearly.
int bend_joint(const deform::Model& model, std::uint32_t v, const std::vector<bool>& linear) {
  for (int k = 0; k < deform::kInfluences; ++k)
    if (model.skin_weights[v][k] > 0.0f && model.skin_joints[v][k] < linear.size() &&
        linear[model.skin_joints[v][k]])
      return -1;
  std::array<int, deform::kInfluences> order;
  for (int k = 0; k < deform::kInfluences; ++k) order[k] = k;
  const auto& weights = model.skin_weights[v];
  std::sort(order.begin(), order.end(), [&](int a, int b) { return weights[a] > weights[b]; });
  if (weights[order[1]] <= 0.0f) return -1;
  const int first = model.skin_joints[v][order[0]], second = model.skin_joints[v][order[1]];
  if (model.skeleton.joints[first].parent == second) return first;
  if (model.skeleton.joints[second].parent == first) return second;
  return -1;
}

// The share of a vertex's two strongest influences (bend_joint's pair) that is `bend`'s.
float bend_share(const deform::Model& model, std::uint32_t v, int bend) {
  const int parent = model.skeleton.joints[bend].parent;
  float own = 0.0f, pair = 0.0f;
  for (int k = 0; k < deform::kInfluences; ++k) {
    const int joint = model.skin_joints[v][k];
    if (joint == bend) own += model.skin_weights[v][k];
    if (joint == bend || joint == parent) pair += model.skin_weights[v][k];
  }
  return pair > 0.0f ? own / pair : 0.0f;
}

// How far the sweep turns a vertex near joint `bend` towards the bone across it (0 to 0.5):
// half at the joint key, none from the link key on, falling as the square of what is left of
// that span (the keys' B-spline basis eases in: the heavy female's thigh vertex 1.6 cm above her
// knee, 0.09 of the span, turned 0.42 of her 66° bend; linearly to 0.5 at the joint, the
// mannequin's knee, held fallen forwards, slid 2.8 cm, past 2.5). By its rest distance from
// the joint along its own bone: the parent's on the parent's side of the joint, else the child
// bone it lies nearest. Also gives that side.
struct SweepTurn {
  float share = 0.0f;
  bool parent_side = true;
};
SweepTurn sweep_turn(const deform::Model& model, const std::vector<glm::mat4>& rest_world,
                     const glm::vec3& rest, int bend) {
  const glm::vec3 joint(rest_world[bend][3]);
  const int parent = model.skeleton.joints[bend].parent;
  const glm::vec3 bone = joint - glm::vec3(rest_world[parent][3]);
  const auto share = [](float along, float link) {
    const float span = link / static_cast<float>(kLinkKeysPerLink + 1);
    const float left = span > 1e-6f ? std::max(0.0f, 1.0f - along / span) : 0.0f;
    return 0.5f * left * left;
  };
  if (glm::dot(rest - joint, bone) < 0.0f && glm::length(bone) > 1e-6f)
    return {share(-glm::dot(rest - joint, glm::normalize(bone)), glm::length(bone)), true};
  float nearest = std::numeric_limits<float>::infinity();
  SweepTurn turn{0.0f, false};
  for (int child = 0; child < model.skeleton.size(); ++child) {
    if (model.skeleton.joints[child].parent != bend) continue;
    const glm::vec3 link = glm::vec3(rest_world[child][3]) - joint;
    const float length = glm::length(link);
    if (length < 1e-6f) continue;
    const float along = glm::clamp(glm::dot(rest - joint, link) / length, 0.0f, length);
    const float distance = glm::distance(rest, joint + link * (along / length));
    if (distance < nearest) nearest = distance, turn.share = share(along, length);
  }
  return turn;
}

}  // namespace

BodySamples::BodySamples(const deform::Model& model, const std::vector<bool>& linear) {
  const int joints = model.skeleton.size();
  const std::vector<glm::vec3> directions = sphere_directions();
  // Parts: each joint's skin, and each bent joint's skin in kBendBands bands by its share.
  const int parts = joints * (1 + kBendBands);
  std::vector<std::uint32_t> best(static_cast<std::size_t>(parts) * kDirections,
                                  std::numeric_limits<std::uint32_t>::max());
  std::vector<float> reach(best.size(), -std::numeric_limits<float>::infinity());
  const auto compete = [&](int part, std::uint32_t v) {
    for (int d = 0; d < kDirections; ++d) {
      const std::size_t slot = static_cast<std::size_t>(part) * kDirections + d;
      const float along = glm::dot(model.positions[v], directions[d]);
      if (along > reach[slot]) reach[slot] = along, best[slot] = v;
    }
  };
  for (std::uint32_t v = 0; v < model.vertex_count(); ++v) {
    compete(model.strongest_joint(v), v);
    if (const int bend = bend_joint(model, v, linear); bend >= 0) {
      const float share = bend_share(model, v, bend);
      const int band = std::min(kBendBands - 1, static_cast<int>(share * kBendBands));
      compete(joints + bend * kBendBands + band, v);
    }
  }
  best.erase(std::remove(best.begin(), best.end(), std::numeric_limits<std::uint32_t>::max()),
             best.end());
  std::sort(best.begin(), best.end());
  best.erase(std::unique(best.begin(), best.end()), best.end());
  vertex_ = std::move(best);
  const std::vector<glm::mat4> rest_world = model.skeleton.world_rest_matrices();
  for (std::uint32_t v : vertex_) {
    rest_.push_back(model.positions[v]);
    joint_.push_back(model.strongest_joint(v));
    skin_joints_.push_back(model.skin_joints[v]);
    skin_weights_.push_back(model.skin_weights[v]);
    bend_joint_.push_back(bend_joint(model, v, linear));
    const int bend = bend_joint_.back();
    bend_rest_.push_back(bend < 0 ? glm::vec3(0.0f) : glm::vec3(rest_world[bend][3]));
    const int parent = bend < 0 ? -1 : model.skeleton.joints[bend].parent;
    bend_parent_.push_back(parent);
    const glm::vec3 bone =
        parent < 0 ? glm::vec3(0.0f) : glm::vec3(rest_world[bend][3] - rest_world[parent][3]);
    bend_bone_.push_back(glm::length(bone) > 1e-6f ? glm::normalize(bone) : glm::vec3(0.0f));
    SweepTurn turn;
    if (bend >= 0) {
      turn = sweep_turn(model, rest_world, model.positions[v], bend);
      // Where linear blending turns it further already, its blend stands.
      const float across_share = bend_share(model, v, bend);
      if (turn.share <= (turn.parent_side ? across_share : 1.0f - across_share)) turn.share = 0.0f;
    }
    sweep_turn_.push_back(turn.share);
    sweep_turn_parent_side_.push_back(turn.parent_side);
  }
}

glm::vec3 BodySamples::position(std::size_t i, std::span<const glm::mat4> skinning) const {
  const glm::vec4 rest(rest_[i], 1.0f);
  glm::vec3 p(0.0f);
  for (int k = 0; k < deform::kInfluences; ++k) {
    const float w = skin_weights_[i][k];
    if (w != 0.0f) p += w * glm::vec3(skinning[skin_joints_[i][k]] * rest);
  }
  return p;
}

float BodySamples::height(std::size_t i, std::span<const glm::mat4> skinning) const {
  const glm::vec3& rest = rest_[i];
  float y = 0.0f;
  for (int k = 0; k < deform::kInfluences; ++k) {
    const float w = skin_weights_[i][k];
    if (w == 0.0f) continue;
    const glm::mat4& m = skinning[skin_joints_[i][k]];
    y += w * (m[0].y * rest.x + m[1].y * rest.y + m[2].y * rest.z + m[3].y);
  }
  return y;
}

float BodySamples::swept_height(std::size_t i, std::span<const glm::mat4> skinning) const {
  if (bend_joint_[i] < 0) return height(i, skinning);
  const glm::vec3 blended = position(i, skinning);
  const glm::vec3 centre(skinning[bend_joint_[i]] * glm::vec4(bend_rest_[i], 1.0f));
  const float drawn_in = glm::distance(blended, centre);
  if (drawn_in < 1e-6f) return blended.y;
  const glm::vec4 rest(rest_[i], 1.0f);
  float kept = 0.0f;
  for (int k = 0; k < deform::kInfluences; ++k) {
    const float w = skin_weights_[i][k];
    if (w != 0.0f)
      kept += w * glm::distance(glm::vec3(skinning[skin_joints_[i][k]] * rest), centre);
  }
  glm::vec3 out = (blended - centre) * (kept / drawn_in);
  if (const float turn = sweep_turn_[i]; turn > 0.0f) {
    // The sweep's frame there: its own bone's turned `turn` of the way to the other's.
    const int own = sweep_turn_parent_side_[i] ? bend_parent_[i] : bend_joint_[i];
    const int other = sweep_turn_parent_side_[i] ? bend_joint_[i] : bend_parent_[i];
    const glm::vec3 offset = rest_[i] - bend_rest_[i];
    const glm::vec3 turned = glm::mix(glm::mat3(skinning[own]) * offset,
                                      glm::mat3(skinning[other]) * offset, turn);
    if (glm::length(turned) > 1e-6f) out = glm::normalize(turned) * kept;
  }
  // The mitre: across the outside of the bend the joint's section is 1 / cos(bend / 2) as long.
  const glm::vec3 before = glm::mat3(skinning[bend_parent_[i]]) * bend_bone_[i];
  const glm::vec3 after = glm::mat3(skinning[bend_joint_[i]]) * bend_bone_[i];
  const glm::vec3 corner = before - after;  // from the joint towards the outside of the bend
  const float cos_half = std::sqrt(std::max(0.0f, 0.5f * (1.0f + glm::dot(before, after))));
  if (const float across = glm::dot(out, corner); across > 0.0f && glm::length(corner) > 1e-6f) {
    const float stretch = 1.0f / std::max(cos_half, kMitreCosHalfBendLimit) - 1.0f;
    out += stretch * across / glm::dot(corner, corner) * corner;
  }
  return centre.y + out.y;
}

}  // namespace sweepd::motion
