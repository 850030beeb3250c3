#include "deform/rig/rig_map.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <functional>
#include <glm/gtc/quaternion.hpp>
#include <stdexcept>
#include <utility>

#include "deform/rig/rig_topology.h"
#include "tests/deform/synthetic_humanoid.h"

namespace sweepd::deform::rig_map_test {
namespace {

// The synthetic humanoids' namespace, not sweepd::deform::test (tests/deform/shared_male.h).
namespace test = sweepd::test;
using test::HumanoidSpec;
using test::SkeletonNode;

std::vector<std::string> names_of(const Skeleton& skeleton, const std::vector<int>& chain) {
  std::vector<std::string> names;
  for (int j : chain) names.push_back(j >= 0 ? skeleton.joints[j].name : "<none>");
  return names;
}

// The index of the spec's sided joint name, -1 where the spec has no such role.
int joint_of(const Skeleton& skeleton, const HumanoidSpec& spec, const std::string& pattern,
             bool left) {
  return pattern.empty() ? -1 : skeleton.find(test::sided(spec, pattern, left));
}

// Every chain and role of the map against the names the skeleton was built with.
void expect_map_follows_spec(const RigMap& map, const Skeleton& skeleton,
                             const HumanoidSpec& spec) {
  EXPECT_EQ(names_of(skeleton, map.torso.chain), spec.torso);
  EXPECT_EQ(names_of(skeleton, map.neck.chain), spec.neck);
  EXPECT_EQ(map.neck.head, skeleton.find(spec.neck.back()));
  for (const bool left : {true, false}) {
    SCOPED_TRACE(left ? "left side" : "right side");
    const ArmJoints& arm = left ? map.left_arm : map.right_arm;
    const LegJoints& leg = left ? map.left_leg : map.right_leg;
    const std::array<int, 4> arm_roles{arm.clavicle, arm.upper, arm.lower, arm.hand};
    const std::array<int, 5> leg_roles{leg.hip, leg.upper, leg.lower, leg.foot, leg.toe};
    for (int i = 0; i < 4; ++i)
      EXPECT_EQ(arm_roles[i], joint_of(skeleton, spec, spec.arm[i], left));
    for (int i = 0; i < 5; ++i)
      EXPECT_EQ(leg_roles[i], joint_of(skeleton, spec, spec.leg[i], left));
  }
}

// Adds `name` halfway between `parent` and its child `child`, which then hangs below it.
void insert_between(std::vector<SkeletonNode>& nodes, const std::string& parent,
                    const std::string& child, const std::string& name) {
  auto find = [&](const std::string& n) {
    return std::find_if(nodes.begin(), nodes.end(),
                        [&](const auto& node) { return node.name == n; });
  };
  const glm::vec3 middle = 0.5f * (find(parent)->world + find(child)->world);
  find(child)->parent = name;
  nodes.push_back({name, parent, middle});
}

void add_child(std::vector<SkeletonNode>& nodes, const std::string& parent, const std::string& name,
               glm::vec3 offset) {
  const auto it = std::find_if(nodes.begin(), nodes.end(),
                               [&](const auto& node) { return node.name == parent; });
  nodes.push_back({name, parent, it->world + offset});
}

void remove_joints(std::vector<SkeletonNode>& nodes, const std::vector<std::string>& names) {
  std::erase_if(nodes, [&](const auto& node) {
    return std::find(names.begin(), names.end(), node.name) != names.end();
  });
}

struct ConventionCase {
  std::string convention;
  HumanoidSpec spec;
  std::function<void(std::vector<SkeletonNode>&)> edit;  // extra joints a real rig would have
};

HumanoidSpec mixamo_spec() {
  return {{"mixamorig:Hips", "mixamorig:Spine", "mixamorig:Spine1", "mixamorig:Spine2"},
          {"mixamorig:Neck", "mixamorig:Head"},
          {"mixamorig:*Shoulder", "mixamorig:*Arm", "mixamorig:*ForeArm", "mixamorig:*Hand",
           "mixamorig:*HandIndex1"},
          {"", "mixamorig:*UpLeg", "mixamorig:*Leg", "mixamorig:*Foot", "mixamorig:*ToeBase"}};
}

HumanoidSpec cmu_3dsmax_spec() {
  return {{"Hips", "Chest", "Chest2"},
          {"Neck", "Head"},
          {"*Collar", "*Shoulder", "*Elbow", "*Wrist", ""},
          {"", "*Hip", "*Knee", "*Ankle", "*Toe"},
          30.0f};
}

HumanoidSpec unreal_spec() {
  return {{"pelvis", "spine_01", "spine_02", "spine_03", "spine_04", "spine_05"},
          {"neck_01", "neck_02", "head"},
          {"clavicle_*", "upperarm_*", "lowerarm_*", "hand_*", "index_01_*"},
          {"", "thigh_*", "calf_*", "foot_*", "ball_*"},
          45.0f,
          "l",
          "r",
          "L",
          "R",
          "root"};
}

void add_unreal_helpers(std::vector<SkeletonNode>& nodes) {
  for (const std::string side : {"l", "r"}) {
    add_child(nodes, "upperarm_" + side, "upperarm_twist_01_" + side, {0, -0.01f, 0});
    add_child(nodes, "thigh_" + side, "thigh_twist_01_" + side, {0, -0.15f, 0});
  }
  add_child(nodes, "root", "ik_foot_root", {0, 0, 0});
  add_child(nodes, "ik_foot_root", "ik_foot_l", {0.1f, 0.08f, 0});
}

// Rigify's deform bones, with or without their "DEF-" prefix.
HumanoidSpec rigify_spec(const std::string& p) {
  return {{p + "spine", p + "spine.001", p + "spine.002", p + "spine.003"},
          {p + "spine.004", p + "spine.005", p + "spine.006"},
          {p + "shoulder.%", p + "upper_arm.%", p + "forearm.%", p + "hand.%", ""},
          {"", p + "thigh.%", p + "shin.%", p + "foot.%", p + "toe.%"},
          40.0f};
}

// Rigify's deform rig splits the long bones in two segments.
std::function<void(std::vector<SkeletonNode>&)> add_rigify_segments(const std::string& prefix) {
  return [prefix](std::vector<SkeletonNode>& nodes) {
    for (const std::string side : {"L", "R"}) {
      insert_between(nodes, prefix + "upper_arm." + side, prefix + "forearm." + side,
                     prefix + "upper_arm." + side + ".001");
      insert_between(nodes, prefix + "thigh." + side, prefix + "shin." + side,
                     prefix + "thigh." + side + ".001");
    }
  };
}

HumanoidSpec smpl_spec() {
  return {{"Pelvis", "Spine1", "Spine2", "Spine3"},
          {"Neck", "Head"},
          {"%_Collar", "%_Shoulder", "%_Elbow", "%_Wrist", "%_Hand"},
          {"", "%_Hip", "%_Knee", "%_Ankle", "%_Foot"}};
}

// SMPL-X spells the same joints in lower case with long sides: matching ignores case.
HumanoidSpec smplx_spec() {
  return {{"pelvis", "spine1", "spine2", "spine3"},
          {"neck", "head"},
          {"*_collar", "*_shoulder", "*_elbow", "*_wrist", ""},
          {"", "*_hip", "*_knee", "*_ankle", "*_foot"},
          20.0f,
          "left",
          "right"};
}

HumanoidSpec vrm_spec() {
  return {{"hips", "spine", "chest", "upperChest"},
          {"neck", "head"},
          {"*Shoulder", "*UpperArm", "*LowerArm", "*Hand", "*IndexProximal"},
          {"", "*UpperLeg", "*LowerLeg", "*Foot", "*Toes"},
          0.0f,
          "left",
          "right"};
}

// Names the case in test listings (else gtest dumps the object's bytes into every test name).
void PrintTo(const ConventionCase& c, std::ostream* out) { *out << c.convention; }

class RigMapConventionTest : public testing::TestWithParam<ConventionCase> {};

TEST_P(RigMapConventionTest, DetectsConventionAndEveryChain) {
  const ConventionCase& c = GetParam();
  std::vector<SkeletonNode> nodes = test::humanoid_nodes(c.spec);
  if (c.edit) c.edit(nodes);
  const Skeleton skeleton = test::make_skeleton(nodes);
  ASSERT_EQ(skeleton.size(), static_cast<int>(nodes.size())) << "test skeleton lost joints";
  const RigMap map = detect_rig_map(skeleton);
  EXPECT_EQ(map.convention, c.convention);
  expect_map_follows_spec(map, skeleton, c.spec);
  EXPECT_EQ(validate_rig_map(map, skeleton), "");
  const std::string text = describe(map, skeleton);
  EXPECT_NE(text.find("left arm: "), std::string::npos) << text;
  EXPECT_NE(text.find(test::sided(c.spec, c.spec.arm[1], true)), std::string::npos) << text;
}

INSTANTIATE_TEST_SUITE_P(
    Conventions, RigMapConventionTest,
    testing::Values(
        ConventionCase{"cmu_motionbuilder", test::cmu_motionbuilder_spec(), {}},
        ConventionCase{
            "mixamo", mixamo_spec(),
            [](std::vector<SkeletonNode>& nodes) {
              add_child(nodes, "mixamorig:Head", "mixamorig:HeadTop_End", {0, 0.18f, 0});
              add_child(nodes, "mixamorig:Head", "mixamorig:LeftEye", {0.03f, 0.07f, 0.08f});
            }},
        ConventionCase{"cmu_3dsmax", cmu_3dsmax_spec(), {}},
        ConventionCase{"unreal", unreal_spec(), add_unreal_helpers},
        ConventionCase{"rigify", rigify_spec("DEF-"), add_rigify_segments("DEF-")},
        ConventionCase{"rigify", rigify_spec(""), add_rigify_segments("")},
        ConventionCase{"smpl", smpl_spec(), {}}, ConventionCase{"smpl", smplx_spec(), {}},
        ConventionCase{"vrm", vrm_spec(), {}}),
    [](const testing::TestParamInfo<ConventionCase>& info) {
      return info.param.convention + "_" + std::to_string(info.index);
    });

std::string detection_error(const Skeleton& skeleton) {
  try {
    detect_rig_map(skeleton);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

std::string all_warnings(const RigMap& map) {
  std::string text;
  for (const std::string& w : map.warnings) text += w + "\n";
  return text;
}

TEST(RigMapTest, MissingLeftArmIsAbsentAndNamedInAWarning) {
  // Neither names nor shape find a left arm: the rest maps by name, the arm is left to skinning.
  std::vector<SkeletonNode> nodes = test::humanoid_nodes(test::cmu_motionbuilder_spec());
  remove_joints(nodes, {"LeftShoulder", "LeftArm", "LeftForeArm", "LeftHand", "LeftFingerBase"});
  const Skeleton skeleton = test::make_skeleton(nodes);
  const RigMap map = detect_rig_map(skeleton);
  EXPECT_EQ(map.convention, "cmu_motionbuilder");
  EXPECT_TRUE(map.left_arm.absent());
  EXPECT_EQ(map.found[static_cast<int>(RigPart::kLeftArm)].finding, PartFinding::kAbsent);
  EXPECT_EQ(skeleton.joints[map.right_arm.upper].name, "RightArm");
  EXPECT_EQ(names_of(skeleton, map.torso.chain), test::cmu_motionbuilder_spec().torso);
  EXPECT_EQ(validate_rig_map(map, skeleton), "");
  ASSERT_EQ(map.warnings.size(), 1u) << all_warnings(map);
  const std::string& warning = map.warnings[0];
  EXPECT_NE(warning.find("no left arm found: the left arm is skinned by linear blending"),
            std::string::npos)
      << warning;
  EXPECT_NE(warning.find("no left arm: expected joints like LeftArm/LeftForeArm/LeftHand"),
            std::string::npos)
      << warning;
  EXPECT_NE(warning.find("upperarm_l/lowerarm_l/hand_l"), std::string::npos) << warning;
}

TEST(RigMapTest, ShortRightLegIsAbsentAndNamedInAWarning) {
  // Only the thigh is left: too short a chain for the shape to find a leg either.
  std::vector<SkeletonNode> nodes = test::humanoid_nodes(unreal_spec());
  remove_joints(nodes, {"calf_r", "foot_r", "ball_r"});
  const Skeleton skeleton = test::make_skeleton(nodes);
  const RigMap map = detect_rig_map(skeleton);
  EXPECT_TRUE(map.right_leg.absent());
  EXPECT_EQ(skeleton.joints[map.left_leg.foot].name, "foot_l");
  const std::string warnings = all_warnings(map);
  EXPECT_NE(warnings.find("no right leg found"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("thigh_r/calf_r/foot_r"), std::string::npos) << warnings;
  EXPECT_EQ(warnings.find("left leg"), std::string::npos) << warnings;
}

TEST(RigMapTest, HeadlessSkeletonHasAnAbsentHeadByNamesAndByShape) {
  // No neck and no head: the arms alone meet at the chest.
  const HumanoidSpec spec = test::cmu_motionbuilder_spec();
  std::vector<SkeletonNode> nodes = test::humanoid_nodes(spec);
  remove_joints(nodes, spec.neck);
  const Skeleton named = test::make_skeleton(nodes);
  Skeleton unnamed = named;
  for (int j = 0; j < unnamed.size(); ++j) unnamed.joints[j].name = "bone" + std::to_string(j);
  for (const Skeleton* skeleton : {&named, &std::as_const(unnamed)}) {
    const RigMap map = detect_rig_map(*skeleton);
    SCOPED_TRACE(map.convention);
    EXPECT_FALSE(map.has_head());
    EXPECT_TRUE(map.neck.chain.empty());
    EXPECT_EQ(names_of(named, map.torso.chain), spec.torso);
    EXPECT_EQ(named.joints[map.left_arm.upper].name, "LeftArm");
    EXPECT_EQ(named.joints[map.right_leg.foot].name, "RightFoot");
    EXPECT_EQ(validate_rig_map(map, *skeleton), "");
    ASSERT_EQ(map.warnings.size(), 1u) << all_warnings(map);
    EXPECT_NE(map.warnings[0].find("no head found: the neck and head are skinned"),
              std::string::npos)
        << map.warnings[0];
  }
}

TEST(RigMapTest, ChainAgainstTheHierarchyFallsToTheShape) {
  // The forearm hangs off the clavicle beside the upper arm: the names do not settle the left
  // arm, the shape does (the longest path through the clavicle) and says why.
  std::vector<SkeletonNode> nodes = test::humanoid_nodes(test::cmu_motionbuilder_spec());
  for (SkeletonNode& node : nodes)
    if (node.name == "LeftForeArm") node.parent = "LeftShoulder";
  const Skeleton skeleton = test::make_skeleton(nodes);
  const RigMap map = detect_rig_map(skeleton);
  const PartDetection& arm = map.found[static_cast<int>(RigPart::kLeftArm)];
  EXPECT_EQ(arm.finding, PartFinding::kByShape);
  EXPECT_NE(arm.note.find("left arm: 'LeftForeArm' is not below 'LeftArm'"), std::string::npos)
      << arm.note;
  EXPECT_EQ(map.found[static_cast<int>(RigPart::kRightArm)].finding, PartFinding::kByName);
  EXPECT_EQ(validate_rig_map(map, skeleton), "");
  EXPECT_TRUE(map.warnings.empty()) << all_warnings(map);
}

TEST(RigMapTest, UnnamedChainFailsInTheFallbackWithReason) {
  std::vector<SkeletonNode> nodes;
  for (int i = 0; i < 5; ++i)
    nodes.push_back(
        {"bone" + std::to_string(i), i ? "bone" + std::to_string(i - 1) : "", {0, 0.3f * i, 0}});
  const std::string error = detection_error(test::make_skeleton(nodes));
  EXPECT_NE(error.find("topological fallback failed"), std::string::npos) << error;
  EXPECT_NE(error.find("the legs and the spine"), std::string::npos) << error;
}

TEST(RigMapTest, LabelsEveryJointByBodyPart) {
  std::vector<SkeletonNode> nodes = test::humanoid_nodes(unreal_spec());
  add_unreal_helpers(nodes);
  const Skeleton skeleton = test::make_skeleton(nodes);
  const RigMap map = detect_rig_map(skeleton);
  const std::vector<BodyPart> labels = label_joints(map, skeleton);
  ASSERT_EQ(labels.size(), nodes.size());
  auto label = [&](const std::string& name) { return to_string(labels[skeleton.find(name)]); };
  EXPECT_STREQ(label("root"), "none");
  EXPECT_STREQ(label("ik_foot_l"), "none");
  EXPECT_STREQ(label("pelvis"), "torso");
  EXPECT_STREQ(label("spine_05"), "torso");
  EXPECT_STREQ(label("neck_02"), "neck");
  EXPECT_STREQ(label("head"), "head");
  EXPECT_STREQ(label("clavicle_l"), "left arm");
  EXPECT_STREQ(label("upperarm_twist_01_l"), "left arm");
  EXPECT_STREQ(label("index_01_r"), "right hand");
  EXPECT_STREQ(label("thigh_twist_01_r"), "right leg");
  EXPECT_STREQ(label("ball_l"), "left foot");
  const std::vector<int> roots = map.skinned_part_roots();
  EXPECT_EQ(names_of(skeleton, roots),
            (std::vector<std::string>{"head", "hand_l", "hand_r", "foot_l", "foot_r"}));
}

// RiggedFigure (Khronos sample, shared data) has unnamed joints; these are its joints' world
// rest positions once its root matrix turned it Y-up (read from the .gltf, rounded to 0.1 mm),
// named by glTF node index. It faces +Z: node 16's arm and node 7's leg are on +X, its left.
std::vector<SkeletonNode> rigged_figure_nodes() {
  return {{"joint_2", "", {0, 0.686f, 0}},
          {"joint_11", "joint_2", {0, 0.857f, -0.013f}},
          {"joint_12", "joint_11", {0, 1.075f, -0.010f}},
          {"joint_19", "joint_12", {0, 1.1265f, 0.0005f}},
          {"joint_20", "joint_19", {0, 1.193f, 0.001f}},
          {"joint_16", "joint_12", {0.088f, 1.074f, -0.010f}},
          {"joint_13", "joint_12", {-0.088f, 1.074f, -0.010f}},
          {"joint_17", "joint_16", {0.306f, 0.964f, -0.023f}},
          {"joint_14", "joint_13", {-0.306f, 0.964f, -0.023f}},
          {"joint_18", "joint_17", {0.447f, 0.8816f, 0.065f}},
          {"joint_15", "joint_14", {-0.447f, 0.8816f, 0.065f}},
          {"joint_7", "joint_2", {0.068f, 0.614f, 0.001f}},
          {"joint_3", "joint_2", {-0.068f, 0.614f, 0.001f}},
          {"joint_8", "joint_7", {0.0771f, 0.3542f, 0.058f}},
          {"joint_4", "joint_3", {-0.0771f, 0.3542f, 0.058f}},
          {"joint_9", "joint_8", {0.0785f, 0.085f, -0.002f}},
          {"joint_5", "joint_4", {-0.0785f, 0.085f, -0.002f}},
          {"joint_10", "joint_9", {0.0796f, 0.022f, 0.0325f}},
          {"joint_6", "joint_5", {-0.0796f, 0.022f, 0.0325f}}};
}

// Turns the whole skeleton by `rotation` about the origin (through its root joint).
Skeleton rotated(Skeleton skeleton, const glm::quat& rotation) {
  Joint& root = skeleton.joints[0];
  root.rest_translation = rotation * root.rest_translation;
  root.rest_rotation = rotation * root.rest_rotation;
  return skeleton;
}

void expect_rigged_figure_map(const RigMap& map, const Skeleton& skeleton,
                              const std::string& left_arm_upper) {
  const bool mirrored = left_arm_upper != "joint_16";
  using Names = std::vector<std::string>;
  EXPECT_EQ(map.convention, "topological");
  EXPECT_EQ(names_of(skeleton, map.torso.chain), (Names{"joint_2", "joint_11", "joint_12"}));
  EXPECT_EQ(names_of(skeleton, map.neck.chain), (Names{"joint_19", "joint_20"}));
  const Names arm_plus_x{"joint_16", "joint_17", "joint_18"};
  const Names arm_minus_x{"joint_13", "joint_14", "joint_15"};
  const Names leg_plus_x{"joint_7", "joint_8", "joint_9", "joint_10"};
  const Names leg_minus_x{"joint_3", "joint_4", "joint_5", "joint_6"};
  EXPECT_EQ(names_of(skeleton, map.left_arm.chain()), mirrored ? arm_minus_x : arm_plus_x);
  EXPECT_EQ(names_of(skeleton, map.right_arm.chain()), mirrored ? arm_plus_x : arm_minus_x);
  EXPECT_EQ(names_of(skeleton, map.left_leg.chain()), mirrored ? leg_minus_x : leg_plus_x);
  EXPECT_EQ(names_of(skeleton, map.right_leg.chain()), mirrored ? leg_plus_x : leg_minus_x);
  EXPECT_EQ(map.left_leg.toe, map.left_leg.chain().back()) << "the last leg joint is the toe";
  EXPECT_EQ(skeleton.joints[map.neck.head].name, "joint_20");
}

TEST(RigMapTopologyTest, RiggedFigureYUp) {
  const Skeleton skeleton = test::make_skeleton(rigged_figure_nodes());
  expect_rigged_figure_map(detect_rig_map(skeleton), skeleton, "joint_16");
}

TEST(RigMapTopologyTest, RiggedFigureZUpAsStoredInTheFile) {
  // The file's joints are Z-up (its root matrix turns them Y-up): up is found, not assumed.
  const Skeleton skeleton = rotated(test::make_skeleton(rigged_figure_nodes()),
                                    glm::angleAxis(glm::radians(90.0f), glm::vec3(1, 0, 0)));
  EXPECT_NEAR(skeleton.world_rest_matrices()[4][3].z, 1.193f, 1e-5f)
      << "head should now be 1.193 m up Z (float rounding only)";
  expect_rigged_figure_map(detect_rig_map(skeleton), skeleton, "joint_16");
}

TEST(RigMapTopologyTest, RiggedFigureTurnedAroundKeepsItsOwnLeft) {
  // Facing -Z, its left arm is on -X: the toes, not the +X axis, decide left from right.
  const Skeleton skeleton = rotated(test::make_skeleton(rigged_figure_nodes()),
                                    glm::angleAxis(glm::radians(180.0f), glm::vec3(0, 1, 0)));
  EXPECT_LT(skeleton.world_rest_matrices()[skeleton.find("joint_16")][3].x, 0.0f);
  expect_rigged_figure_map(detect_rig_map(skeleton), skeleton, "joint_16");
}

TEST(RigMapTopologyTest, RiggedFigureMirroredSwapsSides) {
  std::vector<SkeletonNode> nodes = rigged_figure_nodes();
  for (SkeletonNode& node : nodes) node.world.x = -node.world.x;
  const Skeleton skeleton = test::make_skeleton(nodes);
  expect_rigged_figure_map(detect_rig_map(skeleton), skeleton, "joint_13");
}

// A low-poly game rig: legs, arms and neck all hang from the root, with no spine between.
TEST(RigMapTopologyTest, OneJointTorsoOfAGameRig) {
  std::vector<SkeletonNode> nodes;
  for (SkeletonNode node : rigged_figure_nodes()) {
    if (node.name == "joint_11" || node.name == "joint_12") continue;
    if (node.parent == "joint_12") node.parent = "joint_2";
    nodes.push_back(node);
  }
  for (const glm::quat& turn : {glm::quat(1, 0, 0, 0),
                                glm::angleAxis(glm::radians(90.0f), glm::vec3(1, 0, 0)),
                                glm::angleAxis(glm::radians(180.0f), glm::vec3(0, 1, 0))}) {
    const Skeleton skeleton = rotated(test::make_skeleton(nodes), turn);
    const RigMap map = detect_rig_map(skeleton);
    using Names = std::vector<std::string>;
    EXPECT_EQ(names_of(skeleton, map.torso.chain), (Names{"joint_2"}));
    EXPECT_EQ(names_of(skeleton, map.neck.chain), (Names{"joint_19", "joint_20"}));
    EXPECT_EQ(names_of(skeleton, map.left_arm.chain()), (Names{"joint_16", "joint_17", "joint_18"}));
    EXPECT_EQ(names_of(skeleton, map.right_arm.chain()), (Names{"joint_13", "joint_14", "joint_15"}));
    EXPECT_EQ(names_of(skeleton, map.left_leg.chain()),
              (Names{"joint_7", "joint_8", "joint_9", "joint_10"}));
    EXPECT_EQ(names_of(skeleton, map.right_leg.chain()),
              (Names{"joint_3", "joint_4", "joint_5", "joint_6"}));
    EXPECT_EQ(validate_rig_map(map, skeleton), "");
    // Up from the hips to the shoulders: the turned skeleton's own, within 10° (the shoulders
    // sit 1 cm behind the hips).
    const glm::vec3 up = rest_torso_up(map, skeleton.world_rest_matrices());
    EXPECT_GT(glm::dot(up, turn * glm::vec3(0, 1, 0)), std::cos(glm::radians(10.0f)));
    // The torso's sweep runs from the root up to the neck's first joint: nothing to warn of.
    EXPECT_EQ(names_of(skeleton, map.torso_sweep_chain()), (Names{"joint_2", "joint_19"}));
    EXPECT_TRUE(map.warnings.empty()) << all_warnings(map);
  }
}

TEST(RigMapTopologyTest, AgreesWithNamesOnTheCmuSkeleton) {
  // Clavicles, hip links, fingers and toes are all placed by geometry alone here.
  const HumanoidSpec spec = test::cmu_motionbuilder_spec();
  const Skeleton skeleton = test::make_humanoid(spec);
  const RigMap map = detect_rig_map_by_topology(skeleton);
  EXPECT_EQ(map.convention, "topological");
  expect_map_follows_spec(map, skeleton, spec);
}

}  // namespace
}  // namespace sweepd::deform::rig_map_test
