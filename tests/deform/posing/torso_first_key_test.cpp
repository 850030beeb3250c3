// The torso's first key (at the hips) turns with the hips, also where a root joint sits above
// them (Mixamo-to-Unity's "Root", Unreal's "Root" above the pelvis). A joint key turns halfway
// between its upper and lower link, but the hips have no upper link on the body: halfway to a
// root that the clip leaves at rest while the hips take the body's heading turned the waist
// through half that heading against the chest. The corpus child turned about (cmu_01_01 frame
// 1200, hips 185° from rest) showed a band round its waist stretched 3.13x where LBS and DQS
// stretch nothing (issue 47); the heavy male (Unreal) twisted the same way.
// Measured here: the body turned about its vertical at the hips, every other joint at rest — a
// rigid turn, which the sweep must reproduce as LBS does — on the mannequin as built (hips the
// root) and with a root joint added above its hips.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "deform/binding/bind.h"
#include "mannequin/mannequin.h"
#include "tests/deform/shared_male.h"
#include "tests/root_added_model.h"

namespace sweepd::deform::torso_first_key_test {
namespace {

// The largest distance (m) between the sweep's vertices and the rest mesh turned `degrees`
// about the vertical through the hips.
double largest_departure_from_rigid_turn(const BoundModel& bound, float degrees) {
  const Model& model = bound.model;
  const int hips = bound.rig.torso.chain.front();
  const glm::quat turn = glm::angleAxis(glm::radians(degrees), glm::vec3(0, 1, 0));
  Pose pose = rest_pose(model.skeleton);
  // The hips' parent, if any, is at rest with no turn (root_added), so a world turn is a local
  // one applied before the rest rotation.
  pose.local_rotations[hips] = turn * model.skeleton.joints[hips].rest_rotation;
  test::Posing posing(bound);
  const std::vector<glm::vec3> positions = test::deformed(posing, pose, DeformMethod::kSweep);
  const glm::vec3 pivot(model.skeleton.world_rest_matrices()[hips][3]);
  double largest = 0.0;
  for (std::size_t v = 0; v < positions.size(); ++v) {
    const glm::vec3 rigid = pivot + turn * (model.positions[v] - pivot);
    largest = std::max(largest, static_cast<double>(glm::length(positions[v] - rigid)));
  }
  return largest;
}

// 0.1 mm: a rigid turn moves no joint against another, so the sweep reconstructs the rest mesh
// turned, up to float rounding in the posed sample tables (measured 0.003 mm); before the torso's
// first key followed the hips, the mannequin with a root added departed 8.3, 10.8 and 13.9 cm.
constexpr double kRigidTolerance = 1e-4;

TEST(TorsoFirstKey, TheBodyTurnedAtTheHipsTurnsRigidlyWithOrWithoutARootAboveThem) {
  const Model plain = mannequin::make_mannequin({.target_vertices = 6000});
  const Model rooted = test_models::root_added(plain);
  ASSERT_EQ(rooted.validate(), "");
  const BoundModel plain_bound = bind(plain, detect_rig_map(plain.skeleton));
  const BoundModel rooted_bound = bind(rooted, detect_rig_map(rooted.skeleton));
  // The torso starts at the hips, below the added root (joint 0).
  ASSERT_EQ(rooted.skeleton.joints[rooted_bound.rig.torso.chain.front()].parent, 0);
  // 90° and 120°, and 200°: past half a turn, where the halfway rotation goes the short way
  // round (the child's 185°).
  for (const float degrees : {90.0f, 120.0f, 200.0f}) {
    const double as_built = largest_departure_from_rigid_turn(plain_bound, degrees);
    const double with_root = largest_departure_from_rigid_turn(rooted_bound, degrees);
    std::printf("turned %.0f°: hips the root %.2e m, a root above them %.2e m\n", degrees, as_built,
                with_root);
    EXPECT_LE(as_built, kRigidTolerance) << "hips the root, turned " << degrees << "°";
    EXPECT_LE(with_root, kRigidTolerance) << "a root above the hips, turned " << degrees << "°";
  }
}

}  // namespace
}  // namespace sweepd::deform::torso_first_key_test
