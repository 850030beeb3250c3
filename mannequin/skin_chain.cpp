#include "mannequin/skin_chain.h"

#include <algorithm>
#include <limits>

namespace sweepd::mannequin {

namespace {

float distance_to_segment(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b) {
  const glm::vec3 ab = b - a;
  const float length2 = glm::dot(ab, ab);
  const float t = length2 > 0.0f ? std::clamp(glm::dot(p - a, ab) / length2, 0.0f, 1.0f) : 0.0f;
  return glm::length(p - (a + t * ab));
}

glm::vec3 direction(const SkinBone& bone) {
  const glm::vec3 d = bone.end - bone.start;
  const float length = glm::length(d);
  return length > 0.0f ? d / length : glm::vec3(0.0f);
}

// Share of the outer bone at the junction where `outer` starts: 0 well before, 1 well after.
float outer_share(const SkinBone& inner, const SkinBone& outer, const glm::vec3& p) {
  glm::vec3 normal = direction(inner) + direction(outer);
  const float length = glm::length(normal);
  normal = length > 0.0f ? normal / length : direction(outer);
  const float h = std::max(outer.blend_half_width, 1e-6f);
  const float x = std::clamp((glm::dot(p - outer.start, normal) + h) / (2.0f * h), 0.0f, 1.0f);
  return x * x * (3.0f - 2.0f * x);
}

}  // namespace

int chain_skin_weights(const SkinChain& chain, const glm::vec3& p,
                       std::array<JointWeight, 3>& weights) {
  const int n = static_cast<int>(chain.bones.size());
  int nearest = 0;
  float best = std::numeric_limits<float>::max();
  for (int i = 0; i < n; ++i) {
    const float d = distance_to_segment(p, chain.bones[i].start, chain.bones[i].end);
    if (d < best) {
      best = d;
      nearest = i;
    }
  }
  const float previous =
      nearest > 0 ? 1.0f - outer_share(chain.bones[nearest - 1], chain.bones[nearest], p) : 0.0f;
  const float next =
      nearest + 1 < n ? outer_share(chain.bones[nearest], chain.bones[nearest + 1], p) : 0.0f;
  float own = std::max(0.0f, 1.0f - previous - next);
  const float total = own + previous + next;
  int count = 0;
  weights[count++] = {chain.bones[nearest].joint, own / total};
  if (previous > 0.0f) weights[count++] = {chain.bones[nearest - 1].joint, previous / total};
  if (next > 0.0f) weights[count++] = {chain.bones[nearest + 1].joint, next / total};
  return count;
}

}  // namespace sweepd::mannequin
