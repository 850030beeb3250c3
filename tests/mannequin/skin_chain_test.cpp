// Tests of chain_skin_weights on straight and bent chains.
#include "mannequin/skin_chain.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

namespace sweepd::mannequin {

namespace {

// Three 10 cm bones along +Y (joints 7, 8, 9), blending over +-2 cm at each junction.
SkinChain straight_chain() {
  SkinChain chain;
  chain.bones = {{7, {0, 0, 0}, {0, 0.1f, 0}, 0.0f},
                 {8, {0, 0.1f, 0}, {0, 0.2f, 0}, 0.02f},
                 {9, {0, 0.2f, 0}, {0, 0.3f, 0}, 0.02f}};
  return chain;
}

std::map<int, float> weights_at(const SkinChain& chain, const glm::vec3& p) {
  std::array<JointWeight, 3> weights;
  const int count = chain_skin_weights(chain, p, weights);
  std::map<int, float> result;
  for (int k = 0; k < count; ++k) result[weights[k].joint] += weights[k].weight;
  return result;
}

TEST(SkinChain, MidBoneFollowsOneJointAndJunctionsSplitEvenly) {
  const SkinChain chain = straight_chain();
  auto mid = weights_at(chain, {0.03f, 0.15f, 0.0f});
  EXPECT_FLOAT_EQ(mid[8], 1.0f);  // 5 cm from either junction, outside both blend zones
  auto junction = weights_at(chain, {0.03f, 0.2f, 0.0f});
  EXPECT_NEAR(junction[8], 0.5f, 1e-6f);  // smoothstep(0.5) exactly, float rounding
  EXPECT_NEAR(junction[9], 0.5f, 1e-6f);
}

TEST(SkinChain, WeightsSumToOneAndChangeSmoothlyAroundABentJoint) {
  SkinChain chain = straight_chain();
  chain.bones[2].end = {0.1f, 0.2f, 0.0f};  // the last bone turns 90 degrees
  std::map<int, float> previous;
  float largest_step = 0.0f;
  // Walk a quarter circle 3 cm around the bent joint, 1 mm steps.
  for (int i = 0; i <= 47; ++i) {
    const float angle = static_cast<float>(i) / 30.0f;
    const glm::vec3 p =
        glm::vec3(0.0f, 0.2f, 0.0f) + 0.03f * glm::vec3(-std::cos(angle), std::sin(angle), 0.0f);
    std::map<int, float> now = weights_at(chain, p);
    float sum = 0.0f;
    for (const auto& [joint, w] : now) sum += w;
    EXPECT_NEAR(sum, 1.0f, 1e-6f);  // normalised in float
    if (i > 0) {
      float step = 0.0f;
      for (int joint : {7, 8, 9}) step += std::abs(now[joint] - previous[joint]);
      largest_step = std::max(largest_step, step);
    }
    previous = now;
  }
  // Smoothstep across a 4 cm zone has slope at most 1.5 / 4 cm: 1 mm moves a weight by about
  // 0.04 (L1 0.08); a hard switch between bones would jump by 2.
  EXPECT_LT(largest_step, 0.15f);
}

}  // namespace
}  // namespace sweepd::mannequin
