// A legless cut of the mannequin and of the shared male (leg joints removed, the vertices the
// legs carried removed with them, the rest reweighted onto the pelvis), made in memory: the rig
// map says the legs are absent in a warning, the binding sweeps the torso, neck and arms, and a
// pose bends it without garbage.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "deform/binding/bind.h"
#include "deform/rig/rig_map.h"
#include "io/gltf/gltf_load.h"
#include "mannequin/mannequin.h"
#include "tests/deform/rig/legless_cut.h"
#include "tests/deform/rig/same_rig_parts.h"
#include "tests/deform/rig/swept_parts_pose.h"
#include "tests/deform/shared_male.h"

namespace sweepd::deform {
namespace {

void expect_legless_binds_and_poses(const Model& whole) {
  const Model model = test::legless_cut(whole);
  ASSERT_EQ(model.validate(), "");
  ASSERT_LT(model.vertex_count(), whole.vertex_count() * 3 / 4) << "the legs were cut off";
  const RigMap rig = detect_rig_map(model.skeleton);
  EXPECT_TRUE(rig.left_leg.absent());
  EXPECT_TRUE(rig.right_leg.absent());
  ASSERT_FALSE(rig.left_arm.absent());
  ASSERT_FALSE(rig.right_arm.absent());
  ASSERT_TRUE(rig.has_head());
  ASSERT_EQ(rig.warnings.size(), 1u);
  EXPECT_NE(rig.warnings[0].find("no legs found: legs are skinned by linear blending"),
            std::string::npos)
      << rig.warnings[0];
  EXPECT_NE(describe(rig, model.skeleton).find("left leg: absent"), std::string::npos);

  // The same parts from the shape alone, with names that say nothing.
  Skeleton unnamed = model.skeleton;
  for (int j = 0; j < unnamed.size(); ++j) unnamed.joints[j].name = "j" + std::to_string(j);
  const RigMap by_shape = detect_rig_map(unnamed);
  test::expect_same_rig_parts(by_shape, rig);

  const BoundModel bound = bind(model, rig);
  std::vector<BodyPart> swept;
  for (const BoundSweep& sweep : bound.sweeps) swept.push_back(sweep.part);
  EXPECT_EQ(swept, (std::vector<BodyPart>{BodyPart::kTorso, BodyPart::kNeck, BodyPart::kLeftArm,
                                          BodyPart::kRightArm}));

  test::Posing posing(bound);
  const Pose pose = test::swept_parts_pose(model.skeleton, rig);
  const std::vector<glm::vec3> sweep = test::deformed(posing, pose, DeformMethod::kSweep);
  const std::vector<glm::vec3> lbs = test::deformed(posing, pose, DeformMethod::kLbs);
  float moved = 0.0f, from_lbs = 0.0f;
  for (std::size_t v = 0; v < sweep.size(); ++v) {
    ASSERT_TRUE(std::isfinite(sweep[v].x) && std::isfinite(sweep[v].y) && std::isfinite(sweep[v].z))
        << "vertex " << v;
    moved = std::max(moved, glm::distance(sweep[v], model.positions[v]));
    from_lbs = std::max(from_lbs, glm::distance(sweep[v], lbs[v]));
  }
  EXPECT_GT(moved, 0.2f) << "the 70° elbow moves the hand by more than 20 cm";
  // The sweeps correct skinning's volume loss by centimetres, not decimetres: a vertex further
  // than 10 cm from its LBS position would be a binding gone wrong.
  EXPECT_LT(from_lbs, 0.1f);
}

TEST(LeglessModel, MannequinCutAtTheWaistBindsAndPoses) {
  expect_legless_binds_and_poses(mannequin::make_mannequin({.target_vertices = 3000}));
}

TEST(LeglessModel, SharedMaleCutAtTheWaistBindsAndPoses) {
  const std::filesystem::path file =
      std::filesystem::path(SWEEPD_SHARED_DATA) / "models/makehuman_male_cmu.glb";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << "shared data absent: " << file;
  expect_legless_binds_and_poses(io::load_gltf(file));
}

}  // namespace
}  // namespace sweepd::deform
