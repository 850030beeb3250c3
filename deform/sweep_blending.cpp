#include "deform/sweep_blending.h"

#include <algorithm>
#include <array>

namespace sweepd::deform {

namespace {

constexpr int kPartCount = static_cast<int>(BodyPart::kRightFoot) + 1;

float smoothstep01(float x) {
  x = std::clamp(x, 0.0f, 1.0f);
  return x * x * (3.0f - 2.0f * x);
}

// A region between two parallel planes: 0 before the first, 1 after the second.
struct PlanePair {
  glm::vec3 centre{0.0f};
  glm::vec3 direction{0.0f};
  float half_width = 1.0f;
  float weight(glm::vec3 p) const {
    return smoothstep01((glm::dot(p - centre, direction) + half_width) / (2.0f * half_width));
  }
};

// Planes centred at `joint`, orthogonal to the link from `link_from` to `link_to`.
PlanePair planes_at(std::span<const glm::mat4> world_rest, int joint, int link_from, int link_to,
                    float half_width_fraction) {
  const glm::vec3 from(world_rest[link_from][3]), to(world_rest[link_to][3]);
  PlanePair pair;
  pair.centre = glm::vec3(world_rest[joint][3]);
  pair.direction = glm::normalize(to - from);
  pair.half_width = half_width_fraction * glm::length(to - from);
  return pair;
}

}  // namespace

BodyPart end_part(BodyPart sweep_part) {
  switch (sweep_part) {
    case BodyPart::kNeck: return BodyPart::kHead;
    case BodyPart::kLeftArm: return BodyPart::kLeftHand;
    case BodyPart::kRightArm: return BodyPart::kRightHand;
    case BodyPart::kLeftLeg: return BodyPart::kLeftFoot;
    case BodyPart::kRightLeg: return BodyPart::kRightFoot;
    default: return BodyPart::kNone;
  }
}

std::vector<VertexBinding> blend_shares(const Model& model, const RigMap& rig,
                                        std::span<const glm::mat4> world_rest,
                                        std::span<const BoundSweep> sweeps,
                                        const BindOptions& options) {
  const std::vector<BodyPart> joint_part = label_joints(rig, model.skeleton);
  const int sweep_count = static_cast<int>(sweeps.size());
  std::vector<PlanePair> start(sweep_count), finish(sweep_count);
  PlanePair torso_top, torso_bottom;  // beyond the torso's end keys, skinning takes over
  int torso = -1;
  for (int s = 0; s < sweep_count; ++s) {
    const std::vector<int>& chain = sweeps[s].chain;
    const int n = static_cast<int>(chain.size());
    if (sweeps[s].part == BodyPart::kTorso) torso = s;
    start[s] = planes_at(world_rest, chain[0], chain[0], chain[1], options.transition_half_width);
    finish[s] = planes_at(world_rest, chain[n - 1], chain[n - 2], chain[n - 1],
                          options.end_blend_half_width);
    if (s == torso) {
      torso_top = finish[s];
      torso_top.centre += torso_top.half_width * torso_top.direction;
      torso_bottom = planes_at(world_rest, chain[0], chain[1], chain[0], options.end_blend_half_width);
      torso_bottom.centre += torso_bottom.half_width * torso_bottom.direction;
    }
  }

  std::vector<VertexBinding> result(model.vertex_count());
  std::vector<float> share(sweep_count);
  for (std::size_t v = 0; v < model.vertex_count(); ++v) {
    std::array<float, kPartCount> skin{};
    for (int k = 0; k < kInfluences; ++k)
      skin[static_cast<int>(joint_part[model.skin_joints[v][k]])] += model.skin_weights[v][k];
    const glm::vec3 p = model.positions[v];

    float limbs = 0.0f, skinned = skin[static_cast<int>(BodyPart::kNone)];
    for (int s = 0; s < sweep_count; ++s) {
      share[s] = 0.0f;
      if (s == torso) continue;
      const BodyPart part = sweeps[s].part, end = end_part(part);
      const float mask = std::min(
          1.0f, 2.0f * (skin[static_cast<int>(part)] + skin[static_cast<int>(end)]));
      share[s] = start[s].weight(p) * mask;
      limbs += share[s];
    }
    if (limbs > 1.0f)
      for (float& s : share) s /= limbs;
    if (torso >= 0) {
      share[torso] = std::max(0.0f, 1.0f - std::min(limbs, 1.0f));
      // Above the chest key (shoulders, upper chest) and below the pelvis key the torso sweep
      // only extrapolates; the model's own skinning (clavicles, hips) knows better.
      skinned += share[torso] * std::max(torso_top.weight(p), torso_bottom.weight(p));
    }
    for (int s = 0; s < sweep_count; ++s) {
      if (s == torso || share[s] == 0.0f) continue;
      // The hand/foot/head's own skin weight takes over once it passes one half.
      const float end_skin = skin[static_cast<int>(end_part(sweeps[s].part))];
      const float end_share = std::max(finish[s].weight(p), std::clamp(2.0f * end_skin - 1.0f, 0.0f, 1.0f));
      skinned += share[s] * end_share;
    }
    skinned = std::clamp(skinned, 0.0f, 1.0f);

    // Keep the two largest sweep shares, scaled to fill what skinning leaves.
    VertexBinding& binding = result[v];
    for (int s = 0; s < sweep_count; ++s) {
      if (share[s] > binding.weight[0]) {
        binding.weight[1] = binding.weight[0];
        binding.sweep[1] = binding.sweep[0];
        binding.weight[0] = share[s];
        binding.sweep[0] = static_cast<std::int16_t>(s);
      } else if (share[s] > binding.weight[1]) {
        binding.weight[1] = share[s];
        binding.sweep[1] = static_cast<std::int16_t>(s);
      }
    }
    const float kept = binding.weight[0] + binding.weight[1];
    if (kept <= 0.0f || skinned >= 1.0f) {
      binding = VertexBinding{};
      binding.skin_weight = 1.0f;
      continue;
    }
    for (float& w : binding.weight) w *= (1.0f - skinned) / kept;
    binding.skin_weight = 1.0f - binding.weight[0] - binding.weight[1];
    if (binding.weight[1] == 0.0f) binding.sweep[1] = -1;
  }
  return result;
}

}  // namespace sweepd::deform
