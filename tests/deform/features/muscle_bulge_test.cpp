// Muscle bulge (paper §4.3) on the shared male: the upper arm's front grows monotonically as the
// elbow bends, its back stays, and nothing changes at rest or with the bulge off.
#include "deform/features/muscle_bulge.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>

#include "tests/deform/shared_male.h"

namespace sweepd::deform {
namespace {

// The skin around the middle of the left upper arm (vertices whose rest positions lie within
// 1.5 cm of the plane through the middle of shoulder–elbow, orthogonal to it, and within 8 cm of
// the bone; tracked by vertex, so a folded forearm never counts), as its front and back extents
// along +Z in the given positions.
struct Extent {
  float front, back;
};
Extent upper_arm_extent(const Model& model, std::span<const glm::vec3> positions) {
  const glm::vec3 shoulder = test::rest_joint_position(model, "LeftArm");
  const glm::vec3 elbow = test::rest_joint_position(model, "LeftForeArm");
  const glm::vec3 middle = 0.5f * (shoulder + elbow), axis = glm::normalize(elbow - shoulder);
  Extent extent{-1e9f, 1e9f};
  for (std::size_t v = 0; v < positions.size(); ++v) {
    const glm::vec3 offset = model.positions[v] - middle;
    const float along = glm::dot(offset, axis);
    if (std::abs(along) > 0.015f || glm::length(offset - along * axis) > 0.08f) continue;
    extent.front = std::max(extent.front, positions[v].z);
    extent.back = std::min(extent.back, positions[v].z);
  }
  return extent;
}

TEST(MuscleBulge, ActivationIsZeroAtRestOneAtFullFlexionAndMonotone) {
  const MuscleBulgeOptions options;
  EXPECT_EQ(bulge_activation(0.0f, options), 0.0f);
  EXPECT_EQ(bulge_activation(glm::radians(150.0f), options), 1.0f);
  EXPECT_EQ(bulge_activation(glm::radians(170.0f), options), 1.0f);
  float previous = 0.0f;
  for (int d = 1; d <= 150; ++d) {
    const float now = bulge_activation(glm::radians(static_cast<float>(d)), options);
    EXPECT_GT(now, previous) << d;
    previous = now;
  }
}

TEST(MuscleBulge, UpperArmFrontGrowsMonotonicallyWithElbowFlexion) {
  REQUIRE_SHARED_MALE();
  const Model& model = male.model;
  test::Posing plain(male), bulged(male);
  bulged.features.bulge = true;
  const Extent rest = upper_arm_extent(model, model.positions);
  ASSERT_GT(rest.front - rest.back, 0.05f);  // the section was found: an arm is > 5 cm thick
  float previous = rest.front;
  std::printf("elbow  front growth (mm): bulge  plain | back shift (mm)\n");
  for (int degrees = 0; degrees <= 150; degrees += 10) {
    const Pose pose = test::left_elbow_bent(model, static_cast<float>(degrees));
    const Extent with = upper_arm_extent(model, test::deformed(bulged, pose, DeformMethod::kSweep));
    const Extent without =
        upper_arm_extent(model, test::deformed(plain, pose, DeformMethod::kSweep));
    std::printf("%4d   %+6.2f %+6.2f | %+6.2f\n", degrees, 1e3f * (with.front - rest.front),
                1e3f * (without.front - rest.front), 1e3f * (with.back - rest.back));
    EXPECT_GE(with.front, previous - 1e-5f) << degrees;  // monotone (float slack 10 µm)
    previous = with.front;
    // The back of the arm moves less than a tenth of the front's growth (the centre shift).
    EXPECT_LE(std::abs(with.back - without.back), 0.1f * (with.front - without.front) + 1e-5f);
  }
  // At 150° the mid upper arm's front has moved out by several millimetres (2δ with δ = 12 %
  // of the half-axis, ~4 cm, times the profile): a bulge that can be seen.
  EXPECT_GT(previous - rest.front, 0.004f);
}

TEST(MuscleBulge, RestPoseAndOtherSweepsAreUnchanged) {
  REQUIRE_SHARED_MALE();
  test::Posing plain(male), bulged(male);
  bulged.features.bulge = true;
  const Pose rest = rest_pose(male.model.skeleton);
  const auto a = test::deformed(plain, rest, DeformMethod::kSweep);
  const auto b = test::deformed(bulged, rest, DeformMethod::kSweep);
  EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::vec3)));  // zero at rest
  test::deformed(plain, test::left_elbow_bent(male.model, 120.0f), DeformMethod::kSweep);
  test::deformed(bulged, test::left_elbow_bent(male.model, 120.0f), DeformMethod::kSweep);
  for (int s = 0; s < plain.sweep_poser().sweep_count(); ++s) {
    if (male.sweeps[s].part == BodyPart::kLeftArm) continue;
    const auto p = plain.sweep_poser().posed_keys(s), q = bulged.sweep_poser().posed_keys(s);
    for (std::size_t k = 0; k < p.size(); ++k) {
      EXPECT_EQ(p[k].a, q[k].a) << s;
      EXPECT_EQ(p[k].b, q[k].b) << s;
    }
  }
}

}  // namespace
}  // namespace sweepd::deform
