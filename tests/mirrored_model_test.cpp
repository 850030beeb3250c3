// The mirrored copy the tests check every body with (tests/mirrored_model.h): its joint names
// say its sides as its geometry does, whatever the rig's naming convention, so that a mirrored
// body is read as the same kind of body facing the same way, not as one facing backwards.
#include "tests/mirrored_model.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "deform/rig/rig_map.h"
#include "io/gltf/gltf_load.h"
#include "tests/test_paths.h"

namespace sweepd::test_models {
namespace {

TEST(MirroredModel, SwapsTheSideMarkerAfterANamespaceAndInASuffix) {
  EXPECT_EQ(side_swapped("LeftArm"), "RightArm");
  EXPECT_EQ(side_swapped("RightUpLeg"), "LeftUpLeg");
  EXPECT_EQ(side_swapped("LHipJoint"), "RHipJoint");
  EXPECT_EQ(side_swapped("mixamorig:LeftUpLeg"), "mixamorig:RightUpLeg");
  EXPECT_EQ(side_swapped("mixamorig:RightHandIndex1"), "mixamorig:LeftHandIndex1");
  EXPECT_EQ(side_swapped("thigh_l"), "thigh_r");
  EXPECT_EQ(side_swapped("upperarm_R"), "upperarm_L");
  EXPECT_EQ(side_swapped("forearm.L"), "forearm.R");
  // No side marker: unchanged.
  for (const char* name : {"Hips", "mixamorig:Spine1", "Root", "joint_2", "neck_01", "head"})
    EXPECT_EQ(side_swapped(name), name);
}

// Mirroring through x = 0 keeps a body's forward direction but for its x component: each shared
// body, whatever its convention (CMU, Mixamo, Unreal, OpenPose names, or none), faces the same
// way mirrored. Before the namespace and suffix rules, the Mixamo and Unreal bodies' mirrored
// copies kept LeftArm on their right and were read as facing backwards (forward z -1.00).
TEST(MirroredModel, EverySharedBodyMirroredFacesTheWayItFaced) {
  const std::filesystem::path data(SWEEPD_SHARED_DATA);
  int checked = 0;
  for (const char* file :
       {"models/makehuman_male_cmu.glb", "models/RiggedFigure/RiggedFigure.gltf",
        "models/corpus/makehuman_child_mixamo_unity.glb",
        "models/corpus/makehuman_female_old_heavy_mixamo.glb",
        "models/corpus/makehuman_female_slim_openpose.glb",
        "models/corpus/makehuman_male_old_heavy_unreal.glb"}) {
    if (!std::filesystem::exists(data / file)) continue;
    const deform::Model model = io::load_gltf(data / file);
    const deform::Model mirror = mirrored(model);
    const deform::BodyAxes axes = deform::rest_body_axes(
        deform::detect_rig_map(model.skeleton), model.skeleton.world_rest_matrices());
    const deform::BodyAxes mirrored_axes = deform::rest_body_axes(
        deform::detect_rig_map(mirror.skeleton), mirror.skeleton.world_rest_matrices());
    // Both unit vectors from the same joints, mirrored exactly: float rounding only.
    EXPECT_NEAR(mirrored_axes.forward.x, -axes.forward.x, 1e-4) << file;
    EXPECT_NEAR(mirrored_axes.forward.y, axes.forward.y, 1e-4) << file;
    EXPECT_NEAR(mirrored_axes.forward.z, axes.forward.z, 1e-4) << file;
    ++checked;
  }
  if (checked == 0) GTEST_SKIP() << "shared data absent: " << data;
}

}  // namespace
}  // namespace sweepd::test_models
