// Body samples' swept height (motion/body_samples.h): where the sweep keeps a bent joint's
// volume, linear blending draws the skin in towards the joint, and the body floor lifts the body
// by the swept height. A hand-made arm (shoulder at the origin, upper arm 0.3 m along +x,
// forearm 0.25 m) and one vertex 5 cm below the elbow, half on each bone; the elbow bent 90°
// upwards (the forearm along +y), so that vertex is the elbow's underside, the outside of the
// bend:
// - linearly blended it lies 2.5 cm below the elbow (the mean of (0.30, -0.05) and (0.35, 0));
// - swept, moved out to its 5 cm from the elbow and across the outside of the bend by the
//   mitre's 1 / cos(45°): at (0.35, -0.05), 5 cm below the elbow, where the upper arm's
//   underside runs on to the corner of a tube bent at a mitre (the sweep's plane at the joint
//   bisects the bend);
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

TEST(BodySamples, SweptHeightKeepsABentElbowsUndersideAtTheMitresCorner) {
  const deform::Model model = bent_arm_model();
  const BodySamples samples(model);
  ASSERT_EQ(samples.size(), 1u);
  const std::vector<glm::mat4> bent = skinning(model, 90.0f);
  EXPECT_NEAR(samples.height(0, bent), -0.025f, 1e-6f);
  EXPECT_NEAR(samples.swept_height(0, bent), -0.05f, 1e-6f);
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

// Near a joint the sweep turns the skin from its bone's frame towards the joint key's (half-way
// between the two bones) over the span to the link key, whatever its skin weights: the heavy
// female knocked down forwards, a thigh vertex 1.6 cm above her knee bent 66° (knee weight
// 0.017) lay 3.7 cm from its linear blend, turned about 28° with the shin, 2.5 cm below the
// samples' swept height. Here a vertex 2 cm before the elbow and 5 cm below the upper arm
// (shoulder 0.98, elbow 0.02), the elbow bent 90° up; one link key per link puts the upper
// arm's at 0.15 m from the elbow, so the sweep turns it 0.5 * (1 - 0.02 / 0.15)^2 = 0.3756 of
// the way: its offset from the elbow (-0.02, -0.05) mixed with the forearm's (0.05, -0.02) by
// 0.3756 and kept at its 5.385 cm, (0.00863, -0.05316), then the mitre across the outside
// (corner (1, -1), 1 / cos 45° - 1 of its 6.179 cm across): (0.02143, -0.06595), 6.60 cm below
// the elbow (by its linear blend, moved out and mitred only, 5.69). 20 cm before the elbow,
// past the link key, it is not turned: its swept height is as linearly blended and moved out,
// as before. Tolerance 1e-6 m: float round-off of a few products.
TEST(BodySamples, SweptHeightTurnsTheSkinNearAJointAsTheSweepsKeysDo) {
  deform::Model model = bent_arm_model();
  model.positions = {glm::vec3(0.28f, -0.05f, 0.0f)};
  model.skin_weights = {{0.98f, 0.02f, 0.0f, 0.0f}};
  const std::vector<glm::mat4> bent = skinning(model, 90.0f);
  EXPECT_NEAR(BodySamples(model).swept_height(0, bent), -0.065952f, 1e-6f);
  model.positions = {glm::vec3(0.1f, -0.05f, 0.0f)};
  // Linearly blended: 0.98 (0.1, -0.05) + 0.02 (0.35, -0.2) = (0.105, -0.053), 20.21 cm from
  // the elbow, moved out to its 20.62 cm under either bone; it lies along the upper arm, on the
  // corner's inner side (across (1, -1) < 0), so the mitre adds nothing.
  const glm::vec3 blended(0.105f, -0.053f, 0.0f), elbow(0.3f, 0.0f, 0.0f);
  const glm::vec3 out = (blended - elbow) * (std::sqrt(0.2f * 0.2f + 0.05f * 0.05f) /
                                             glm::distance(blended, elbow));
  EXPECT_NEAR(BodySamples(model).swept_height(0, bent), out.y, 1e-6f);
}

// The skin where two bones meet is sampled as a part of its own: a vertex blended across the
// elbow (shoulder 0.6, elbow 0.4) that lies inside the upper arm's skin at rest (a box from
// x = 0 to 0.32 m, 6 cm about the bone, all on the shoulder), so no direction finds it
// furthest among the shoulder's vertices, is still a sample: bent, it is the elbow's underside.
TEST(BodySamples, TheSkinBlendedAcrossAJointIsSampledThoughNoPartReachesFurthestThere) {
  deform::Model model = bent_arm_model();
  model.skin_weights = {{0.6f, 0.4f, 0.0f, 0.0f}};
  for (const float x : {0.0f, 0.32f})
    for (const float y : {-0.06f, 0.06f})
      for (const float z : {-0.06f, 0.06f}) {
        model.positions.emplace_back(x, y, z);
        model.normals.emplace_back(0.0f, 1.0f, 0.0f);
        model.skin_joints.push_back({0, 0, 0, 0});
        model.skin_weights.push_back({1.0f, 0.0f, 0.0f, 0.0f});
      }
  const BodySamples samples(model);
  bool blended_sampled = false;
  for (std::size_t i = 0; i < samples.size(); ++i) blended_sampled |= samples.vertex(i) == 0;
  EXPECT_TRUE(blended_sampled);
  EXPECT_EQ(samples.size(), 9u);  // the box's 8 corners and the blended vertex
}

}  // namespace
}  // namespace sweepd::motion
