// Posing (paper §4.1) on the shared male: rest pose, the fast path against direct evaluation,
// threads, agreement with skinning away from a bent joint, and what each method keeps of a
// limb's cross-section at a 150° twist (a 135° bend: joint_section_test.cpp).
#include "deform/posing/sweep_poser.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <glm/gtc/quaternion.hpp>

#include "deform/binding/bind.h"
#include "deform/job/deform_job.h"
#include "deform/model/forward_kinematics.h"
#include "deform/rig/rig_map.h"
#include "io/gltf/gltf_load.h"
#include "tests/deform/posed_section.h"
#include "tests/deform/shared_male.h"

namespace sweepd::deform::sweep_poser_test {
namespace {

namespace fs = std::filesystem;

float height(const Model& model) {
  float lo = 1e9f, hi = -1e9f;
  for (const glm::vec3& p : model.positions) lo = std::min(lo, p.y), hi = std::max(hi, p.y);
  return hi - lo;
}

glm::vec3 joint_position(const Model& model, const std::string& name) {
  return test::rest_joint_position(model, name);
}

// The rest pose with `joint` turned by `degrees` about a world axis. The male's rest frames are
// world-aligned (translation only), so a local rotation is a world rotation at that joint.
Pose turned(const Model& model, const std::string& joint, glm::vec3 axis, float degrees) {
  Pose pose = rest_pose(model.skeleton);
  test::turn(model, pose, joint, axis, degrees);
  return pose;
}

float max_distance(std::span<const glm::vec3> a, std::span<const glm::vec3> b) {
  float worst = 0.0f;
  for (std::size_t v = 0; v < a.size(); ++v) worst = std::max(worst, glm::length(a[v] - b[v]));
  return worst;
}

TEST(SweepPoser, RestPoseReproducesTheRestMeshWithEveryMethod) {
  REQUIRE_SHARED_MALE();
  test::Posing deformer(male);
  for (DeformMethod method : {DeformMethod::kSweep, DeformMethod::kLbs, DeformMethod::kDqs}) {
    const auto positions = deformed(deformer, rest_pose(male.model.skeleton), method);
    const float error = max_distance(positions, male.model.positions);
    std::printf("rest pose, %s: worst %.3g m\n", to_string(method), error);
    EXPECT_LE(error, 1e-5f * height(male.model)) << to_string(method);  // the bound
  }
}

TEST(SweepPoser, FastPathMatchesDirectEvaluationAndThreadsAreBitIdentical) {
  REQUIRE_SHARED_MALE();
  const Model& model = male.model;
  test::Posing deformer(male);
  Pose pose = turned(model, "LeftForeArm", {0.7f, 0.7f, 0.0f}, 120.0f);
  pose.local_rotations[model.skeleton.find("RightUpLeg")] =
      glm::angleAxis(glm::radians(-80.0f), glm::vec3(1, 0, 0));
  pose.local_rotations[model.skeleton.find("Spine")] =
      glm::angleAxis(glm::radians(30.0f), glm::vec3(0, 1, 0));
  pose.local_rotations[model.skeleton.find("Neck")] =
      glm::angleAxis(glm::radians(25.0f), glm::vec3(1, 0, 1));
  std::vector<glm::vec3> one(model.vertex_count()), three(model.vertex_count());
  Pose copy = pose;
  deformer.deform(copy, DeformMethod::kSweep, one, {}, 1);
  copy = pose;
  deformer.deform(copy, DeformMethod::kSweep, three, {}, 3);
  EXPECT_EQ(0, std::memcmp(one.data(), three.data(), one.size() * sizeof(glm::vec3)));

  float worst = 0.0f;
  for (std::size_t v = 0; v < model.vertex_count(); ++v)
    worst = std::max(worst, glm::length(one[v] - deformer.sweep_poser().reference_position(
                                                     v, deformer.skinning())));
  std::printf("fast path vs direct evaluation: worst %.3g m\n", worst);
  EXPECT_LE(worst, 1e-5f * height(male.model));  // the bound; float rounding is ~1e-7 m
}

TEST(SweepPoser, EveryInstructionSetMatchesDirectEvaluationWithAnyThreadCount) {
  REQUIRE_SHARED_MALE();
  const Model& model = male.model;
  Pose pose = turned(model, "LeftForeArm", {0.7f, 0.7f, 0.0f}, 120.0f);
  pose.local_rotations[model.skeleton.find("LeftUpLeg")] =
      glm::angleAxis(glm::radians(-70.0f), glm::vec3(1, 0, 0));
  pose.local_rotations[model.skeleton.find("Spine")] =
      glm::angleAxis(glm::radians(-20.0f), glm::vec3(0, 0, 1));
  std::vector<glm::mat4> world(model.skeleton.joints.size()), skinning(world.size());
  forward_kinematics(model.skeleton, pose, world);
  skinning_matrices(world, world_rest_inverse_matrices(model.skeleton), skinning);
  std::vector<VertexLoopInstructions> sets = {VertexLoopInstructions::kBaseline};
  if (widest_vertex_loop_instructions() != VertexLoopInstructions::kBaseline)
    sets.push_back(widest_vertex_loop_instructions());
  const std::size_t n = model.vertex_count();
  std::vector<std::vector<glm::vec3>> by_set;
  for (const VertexLoopInstructions set : sets) {
    SweepPoser poser(male, set);
    poser.set_pose(world);
    std::vector<glm::vec3> one(n), one_normals(n), four(n), four_normals(n);
    poser.deform(skinning, one, one_normals, 1);
    poser.deform(skinning, four, four_normals, 4);
    EXPECT_EQ(0, std::memcmp(one.data(), four.data(), n * sizeof(glm::vec3)));
    EXPECT_EQ(0, std::memcmp(one_normals.data(), four_normals.data(), n * sizeof(glm::vec3)));
    float worst = 0.0f;
    for (std::size_t v = 0; v < n; ++v)
      worst = std::max(worst, glm::length(one[v] - poser.reference_position(v, skinning)));
    std::printf("instruction set %d: worst %.3g m from direct evaluation\n", static_cast<int>(set),
                worst);
    EXPECT_LE(worst, 1e-5f * height(model));  // the bound
    by_set.push_back(std::move(one));
  }
  // The sets differ by rounding only (fused multiply-adds, another order of the sums): float
  // rounding at 1-2 m from the origin is ~1e-7 m per operation, some tens of operations.
  for (std::size_t s = 1; s < by_set.size(); ++s) {
    const float apart = max_distance(by_set[0], by_set[s]);
    std::printf("instruction sets 0 and %zu: %.3g m apart\n", s, apart);
    EXPECT_LE(apart, 2e-6f);
  }
}

TEST(SweepPoser, AgreesWithSkinningFarFromABentElbow) {
  REQUIRE_SHARED_MALE();
  const Model& model = male.model;
  test::Posing deformer(male);
  const Pose pose = turned(model, "LeftForeArm", {0.7f, 0.7f, 0.0f}, 90.0f);
  const auto sweep = deformed(deformer, pose, DeformMethod::kSweep);
  const auto lbs = deformed(deformer, pose, DeformMethod::kLbs);
  // Beyond the transition zone: vertices that LBS does not blend across the elbow (no weight on
  // the upper arm and forearm joints at once) and that lie over 1.5 forearm-link key spacings
  // from the elbow (the local C(t) of the arm sweep feels the bend one span on each side).
  const int upper = model.skeleton.find("LeftArm"), lower = model.skeleton.find("LeftForeArm");
  const glm::vec3 elbow = joint_position(model, "LeftForeArm");
  const float spacing = glm::length(joint_position(model, "LeftHand") - elbow) /
                        static_cast<float>(male.options.intermediate_keys_per_link + 1);
  float worst = 0.0f;
  int compared = 0;
  for (std::size_t v = 0; v < model.vertex_count(); ++v) {
    bool on_upper = false, on_lower = false;
    for (int k = 0; k < kInfluences; ++k) {
      on_upper |= model.skin_joints[v][k] == upper && model.skin_weights[v][k] > 0.0f;
      on_lower |= model.skin_joints[v][k] == lower && model.skin_weights[v][k] > 0.0f;
    }
    if ((on_upper && on_lower) || glm::length(model.positions[v] - elbow) < 1.5f * spacing)
      continue;
    worst = std::max(worst, glm::length(sweep[v] - lbs[v]));
    ++compared;
  }
  std::printf("sweep vs LBS beyond the elbow's transition zone (%d vertices): worst %.3g m\n",
              compared, worst);
  EXPECT_GT(compared, static_cast<int>(model.vertex_count()) * 3 / 4);
  EXPECT_LE(worst, 1e-4f * height(male.model));  // the bound
}

TEST(SweepPoser, ForearmTwistedBy150DegreesKeepsItsSections) {
  REQUIRE_SHARED_MALE();
  const Model& model = male.model;
  test::Posing deformer(male);
  test::WeldedMesh welded(model);
  const glm::vec3 elbow = joint_position(model, "LeftForeArm"),
                  wrist = joint_position(model, "LeftHand");
  const glm::vec3 axis = glm::normalize(wrist - elbow);
  // Pronation: the hand turns 150° about the forearm's axis; the forearm's skin must follow
  // without collapsing (LBS's "candy wrapper").
  const Pose pose = turned(model, "LeftHand", axis, 150.0f);
  const auto rest = model.positions;
  std::printf("forearm twisted 150 deg, smallest section / rest:");
  float ratio[3];
  for (DeformMethod m : {DeformMethod::kSweep, DeformMethod::kLbs, DeformMethod::kDqs}) {
    const auto posed = deformed(deformer, pose, m);
    float smallest = 1e9f;
    for (float f = 0.1f; f < 0.95f; f += 0.05f) {
      const glm::vec3 point = glm::mix(elbow, wrist, f);
      const float before = welded.section_area(rest, point, axis);
      const float after = welded.section_area(posed, point, axis);
      if (before > 0.0f) smallest = std::min(smallest, after / before);
    }
    ratio[static_cast<int>(m)] = smallest;
    std::printf(" %s %.3f", to_string(m), smallest);
  }
  std::printf("\n");
  EXPECT_GE(ratio[0], 0.8f);  // the bound for sweep
}

}  // namespace
}  // namespace sweepd::deform::sweep_poser_test
