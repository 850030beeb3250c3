// Spines and necks of other lengths and names than the clip's (issue 48: nothing unmapped in
// silence, and nothing left still that the clip moves): a Mixamo spine (Hips, Spine, Spine1,
// Spine2), an Unreal one (pelvis, spine_01..03) or the RiggedFigure's unnamed one against CMU's
// (Hips, LowerBack, Spine, Spine1) matched neither by name nor by hierarchy past the branching
// pelvis, so their middle joints stayed at rest and the whole bend fell on the chest joint.
// Asserted, on every corpus body with a spine chain and on the RiggedFigure, with both CMU clips'
// skeleton: every joint of the model's torso chain and of its neck chain is driven by a clip
// joint, and a model joint between pelvis and chest is driven by one between the clip's.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "deform/rig/rig_map.h"
#include "io/bvh/bvh_load.h"
#include "io/gltf/gltf_load.h"
#include "motion/clip_up_axis.h"
#include "motion/retarget.h"
#include "tests/test_paths.h"

namespace sweepd::motion {
namespace {

namespace fs = std::filesystem;

class SpineChainPairing : public ::testing::TestWithParam<const char*> {};

TEST_P(SpineChainPairing, EveryTorsoAndNeckJointIsDriven) {
  const fs::path file = fs::path(SWEEPD_SHARED_DATA) / GetParam();
  if (!fs::exists(file)) GTEST_SKIP() << "shared data absent: " << file;
  const deform::Model model = io::load_gltf(file);
  const Clip clip = io::load_bvh(fs::path(SWEEPD_SHARED_DATA) / "motion/cmu_01_01.bvh");
  const Retargeter retargeter(clip, model);
  const deform::RigMap model_map = deform::detect_rig_map(model.skeleton);
  const deform::RigMap clip_map = deform::detect_rig_map(clip_rest_skeleton(clip));
  auto driver = [&](int joint) {
    for (const JointMatch& match : retargeter.matches())
      if (match.model_joint == joint && match.driven) return match.bvh_joint;
    return -1;
  };
  const std::vector<int>& torso = model_map.torso.chain;
  ASSERT_GE(torso.size(), 3u) << "a body with joints between pelvis and chest";
  for (std::size_t i = 0; i < torso.size(); ++i) {
    const int b = driver(torso[i]);
    EXPECT_GE(b, 0) << model.skeleton.joints[torso[i]].name << " is left still";
    if (i == 0 || i + 1 == torso.size() || b < 0) continue;
    const std::vector<int>& clip_torso = clip_map.torso.chain;
    const auto at = std::find(clip_torso.begin(), clip_torso.end(), b);
    EXPECT_TRUE(at != clip_torso.end() && at != clip_torso.begin() && at + 1 != clip_torso.end())
        << model.skeleton.joints[torso[i]].name << " is driven by " << clip.joints[b].name
        << ", not a joint between the clip's pelvis and chest";
  }
  for (int joint : model_map.neck.chain)
    EXPECT_GE(driver(joint), 0) << model.skeleton.joints[joint].name << " is left still";
}

INSTANTIATE_TEST_SUITE_P(Bodies, SpineChainPairing,
                         ::testing::Values("models/corpus/makehuman_female_old_heavy_mixamo.glb",
                                           "models/corpus/makehuman_male_old_heavy_unreal.glb",
                                           "models/corpus/makehuman_child_mixamo_unity.glb",
                                           "models/RiggedFigure/RiggedFigure.gltf",
                                           "models/makehuman_male_cmu.glb"));

}  // namespace
}  // namespace sweepd::motion
