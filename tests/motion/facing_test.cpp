// Facing from the body (issue 48 item 2): a model built facing another way than the clip (turned
// about the vertical, as a Blender armature turned 90°) faces where the clip faces at every
// frame, so it walks along the clip's path instead of sideways.
// Bodies: the shared male (and mirrored), the RiggedFigure, the four corpus bodies and the
// mannequin (4k; its own rig convention).
//
// Figure, per frame: the angle about the vertical between the model's hips (left thigh joint
// minus right, the rig map's leg roles, posed) and the clip's (its LeftUpLeg minus RightUpLeg),
// both made horizontal. Asserted: within 10° at every frame of cmu_01_01 and cmu_01_03 (the
// issue's target), for each body turned 0°, 90° and 180° about the vertical (the turns).
// Measured here: within 0.77° on every body, clip and turn (the rest poses' hips differ
// slightly in splay). Before the facing turn the 90° model stayed 90° off in every frame.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <glm/gtc/quaternion.hpp>
#include <optional>
#include <string>
#include <vector>

#include "deform/model/forward_kinematics.h"
#include "deform/rig/rig_map.h"
#include "io/bvh/bvh_load.h"
#include "io/gltf/gltf_load.h"
#include "motion/retarget.h"
#include "tests/motion/facing_difference.h"
#include "tests/motion/test_bodies.h"
#include "tests/test_paths.h"
#include "tests/turned_model.h"

namespace sweepd::motion {
namespace {

namespace fs = std::filesystem;

using test_models::Body;

class Facing : public testing::TestWithParam<Body> {};

TEST_P(Facing, TurnedModelsFaceTheClipsWayAtEveryFrame) {
  const std::optional<deform::Model> loaded = test_models::load_body(GetParam());
  if (!loaded) GTEST_SKIP() << "shared data absent: " << GetParam().file;
  const deform::Model& model = *loaded;
  for (const char* clip_file : {"motion/cmu_01_01.bvh", "motion/cmu_01_03.bvh"}) {
    const Clip clip = io::load_bvh(fs::path(SWEEPD_SHARED_DATA) / clip_file);
    for (const float degrees : {0.0f, 90.0f, 180.0f}) {
      SCOPED_TRACE(std::string(clip_file) + " turned " + std::to_string(static_cast<int>(degrees)) +
                   "°");
      const deform::Model body = test_models::turned(model, degrees);
      // Feet free: planting and the body floor move the root only up or down and bend the
      // legs, so they leave the hips' yaw as it is (the same figures to 0.01°), and skipping
      // them makes the test a quarter as costly (under ASan 187 s of 8 tests with them).
      const Retargeter retargeter(clip, body, {}, Feet::kFree);
      const float worst = test::worst_facing_difference(body, clip, retargeter);
      std::printf("%s, %s turned %.0f°: worst facing difference %.2f°\n", clip_file,
                  GetParam().file, degrees, worst);
      EXPECT_LT(worst, 10.0f);
      // The turn is said: a warning where the model was built facing another way.
      const std::vector<std::string>& warnings = retargeter.warnings();
      const bool said = std::any_of(warnings.begin(), warnings.end(), [](const std::string& w) {
        return w.find("turned to face the clip's way") != std::string::npos;
      });
      EXPECT_EQ(said, degrees != 0.0f);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Bodies, Facing,
    testing::ValuesIn(test_models::every_body(true)),
    [](const testing::TestParamInfo<Body>& info) {
      return test_models::body_test_name(info.param);
    });

}  // namespace
}  // namespace sweepd::motion
