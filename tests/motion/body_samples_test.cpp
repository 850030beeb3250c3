// Body samples' swept height (motion/body_samples.h): where the sweep keeps a bent joint's
// volume, linear blending draws the skin in towards the joint, and the body floor lifts the body
// by the swept height. A hand-made arm (shoulder at the origin, upper arm 0.3 m along +x,
// forearm 0.25 m) and one vertex 5 cm below the elbow, half on each bone; the elbow bent 90°
// upwards (the forearm along +y), so that vertex is the elbow's underside:
// - linearly blended it lies 2.5 cm below the elbow (the mean of (0.30, -0.05) and (0.35, 0));
// - swept, 5 cm from the elbow along the same direction: 5/sqrt(2) = 3.54 cm below it;
// - straight, both are the rest height, and with the forearm's joint blended linearly (a
//   foot's) the swept height is the linear one.
// Tolerance 1e-6 m: float round-off of a few products.
#include "motion/body_samples.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "deform/model/forward_kinematics.h"

namespace sweepd::motion {
namespace {

deform::Model bent_arm_model() {
  deform::Model model;
  model.skeleton.joints.push_back({"shoulder", -1, glm::vec3(0.0f)});
  model.skeleton.joints.push_back({"elbow", 0, glm::vec3(0.3f, 0.0f, 0.0f)});
  model.skeleton.joints.push_back({"wrist", 1, glm::vec3(0.25f, 0.0f, 0.0f)});
  model.positions = {glm::vec3(0.3f, -0.05f, 0.0f)};
  model.normals = {glm::vec3(0.0f, -1.0f, 0.0f)};
  model.skin_joints = {{0, 1, 0, 0}};
  model.skin_weights = {{0.5f, 0.5f, 0.0f, 0.0f}};
  return model;
}

// Skinning matrices of the arm with its elbow turned `degrees` about +z (+x goes to +y).
std::vector<glm::mat4> skinning(const deform::Model& model, float degrees) {
  deform::Pose pose = deform::rest_pose(model.skeleton);
  pose.local_rotations[1] = glm::angleAxis(glm::radians(degrees), glm::vec3(0, 0, 1));
  std::vector<glm::mat4> world(model.skeleton.joints.size()), matrices(world.size());
  deform::forward_kinematics(model.skeleton, pose, world);
  deform::skinning_matrices(world, deform::world_rest_inverse_matrices(model.skeleton), matrices);
  return matrices;
}

TEST(BodySamples, SweptHeightKeepsABentElbowsUndersideWhereLinearBlendingDrawsItIn) {
  const deform::Model model = bent_arm_model();
  const BodySamples samples(model);
  ASSERT_EQ(samples.size(), 1u);
  const std::vector<glm::mat4> bent = skinning(model, 90.0f);
  EXPECT_NEAR(samples.height(0, bent), -0.025f, 1e-6f);
  EXPECT_NEAR(samples.swept_height(0, bent), -0.05f / std::sqrt(2.0f), 1e-6f);
  const std::vector<glm::mat4> straight = skinning(model, 0.0f);
  EXPECT_NEAR(samples.height(0, straight), -0.05f, 1e-6f);
  EXPECT_NEAR(samples.swept_height(0, straight), -0.05f, 1e-6f);
}

TEST(BodySamples, SweptHeightIsTheLinearOneWhereAnInfluenceBlendsLinearly) {
  const deform::Model model = bent_arm_model();
  const BodySamples samples(model, {false, true, false});
  const std::vector<glm::mat4> bent = skinning(model, 90.0f);
  EXPECT_NEAR(samples.swept_height(0, bent), samples.height(0, bent), 1e-6f);
}

}  // namespace
}  // namespace sweepd::motion
