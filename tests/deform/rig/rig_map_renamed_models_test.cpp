// Rig detection on the shared male and the mannequin with their joints renamed mechanically to
// each naming convention of rig_naming.h, to namespaced/piped/suffixed names, and to meaningless
// names (shape alone): the map must pick the same joint for every part as on the original CMU
// names, and the posed vertices must not move. Nothing is written to disk.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "deform/rig/rig_map.h"
#include "io/gltf/gltf_load.h"
#include "mannequin/mannequin.h"
#include "tests/deform/rig/same_rig_parts.h"
#include "tests/deform/rig/swept_parts_pose.h"
#include "tests/deform/shared_male.h"

namespace sweepd::deform {
namespace {

namespace fs = std::filesystem;

// New name per CMU name; a joint it leaves out becomes "extra_<index>" (a name of no convention).
using Renaming = std::map<std::string, std::string>;

struct Convention {
  std::string name;       // the convention detect_rig_map should report
  std::string test_name;  // a gtest-safe label
  std::function<Renaming()> renaming;
};

// Adds the left and right entries of a sided joint: `cmu` with '*' for Left/Right (or '%' for
// L/R), `renamed` with '*' for the convention's side spelling `left`/`right`.
void add_sided(Renaming& renaming, const std::string& cmu, const std::string& renamed,
               const std::string& left, const std::string& right) {
  for (const bool is_left : {true, false}) {
    auto fill = [&](const std::string& pattern, char star, const std::string& spelling) {
      std::string out;
      for (char c : pattern) out += c == star ? spelling : std::string(1, c);
      return out;
    };
    const std::string source = cmu.find('%') != std::string::npos
                                   ? fill(cmu, '%', is_left ? "L" : "R")
                                   : fill(cmu, '*', is_left ? "Left" : "Right");
    renaming[source] = fill(renamed, '*', is_left ? left : right);
  }
}

// torso: Hips LowerBack Spine Spine1; neck: Neck Neck1 Head; per side: LHipJoint, LeftUpLeg,
// LeftLeg, LeftFoot, LeftToeBase, LeftShoulder, LeftArm, LeftForeArm, LeftHand, LeftFingerBase,
// LeftHandFinger1, LThumb. "" leaves a joint out; `prefix` goes before every new name.
Renaming renaming(const std::vector<std::string>& torso_and_neck,
                  const std::vector<std::string>& sided, const std::string& left,
                  const std::string& right, const std::string& prefix = "") {
  static const std::vector<std::string> kCmuTorso = {"Hips", "LowerBack", "Spine", "Spine1",
                                                     "Neck", "Neck1",     "Head"};
  static const std::vector<std::string> kCmuSided = {
      "%HipJoint", "*UpLeg",   "*Leg",  "*Foot",       "*ToeBase",     "*Shoulder",
      "*Arm",      "*ForeArm", "*Hand", "*FingerBase", "*HandFinger1", "%Thumb"};
  Renaming result;
  for (std::size_t i = 0; i < kCmuTorso.size(); ++i)
    if (!torso_and_neck[i].empty()) result[kCmuTorso[i]] = prefix + torso_and_neck[i];
  for (std::size_t i = 0; i < kCmuSided.size(); ++i)
    if (!sided[i].empty()) add_sided(result, kCmuSided[i], prefix + sided[i], left, right);
  return result;
}

// Blender Rigify's metarig names, or its deform layer's with prefix "DEF-".
Renaming rigify_renaming(const std::string& prefix) {
  return renaming(
      {"spine", "spine.001", "spine.002", "spine.003", "spine.004", "spine.005", "spine.006"},
      {"pelvis.*", "thigh.*", "shin.*", "foot.*", "toe.*", "shoulder.*", "upper_arm.*", "forearm.*",
       "hand.*", "palm.01.*", "f_index.01.*", "thumb.01.*"},
      "L", "R", prefix);
}

std::vector<Convention> conventions() {
  return {
      {"mixamo", "mixamo",
       [] {
         return renaming({"Hips", "Spine", "Spine1", "Spine2", "Neck", "Neck1", "Head"},
                         {"", "*UpLeg", "*Leg", "*Foot", "*ToeBase", "*Shoulder", "*Arm",
                          "*ForeArm", "*Hand", "*HandIndex1", "*HandIndex2", "*HandThumb1"},
                         "Left", "Right", "mixamorig1:");
       }},
      {"unreal", "unreal",
       [] {
         return renaming(
             {"pelvis", "spine_01", "spine_02", "spine_03", "neck_01", "neck_02", "head"},
             {"", "thigh_*", "calf_*", "foot_*", "ball_*", "clavicle_*", "upperarm_*", "lowerarm_*",
              "hand_*", "index_01_*", "index_02_*", "thumb_01_*"},
             "l", "r");
       }},
      {"rigify", "rigify_metarig", [] { return rigify_renaming(""); }},  // the issue's base mesh
      {"rigify", "rigify_def", [] { return rigify_renaming("DEF-"); }},
      {"biped", "biped",
       [] {
         return renaming({"Pelvis", "Spine", "Spine1", "Spine2", "Neck", "Neck1", "Head"},
                         {"", "* Thigh", "* Calf", "* Foot", "* Toe0", "* Clavicle", "* UpperArm",
                          "* Forearm", "* Hand", "* Finger1", "* Finger11", "* Finger0"},
                         "L", "R", "Bip001 ");
       }},
      {"smpl", "smpl",
       [] {
         return renaming({"Pelvis", "Spine1", "Spine2", "Spine3", "Neck", "", "Head"},
                         {"", "*_Hip", "*_Knee", "*_Ankle", "*_Foot", "*_Collar", "*_Shoulder",
                          "*_Elbow", "*_Wrist", "*_Hand", "", ""},
                         "L", "R");
       }},
      {"vrm", "vroid",
       [] {
         return renaming(
             {"J_Bip_C_Hips", "J_Bip_C_Spine", "J_Bip_C_Chest", "J_Bip_C_UpperChest",
              "J_Bip_C_Neck", "", "J_Bip_C_Head"},
             {"", "J_Bip_*_UpperLeg", "J_Bip_*_LowerLeg", "J_Bip_*_Foot", "J_Bip_*_ToeBase",
              "J_Bip_*_Shoulder", "J_Bip_*_UpperArm", "J_Bip_*_LowerArm", "J_Bip_*_Hand",
              "J_Bip_*_Index1", "J_Bip_*_Index2", "J_Bip_*_Thumb1"},
             "L", "R");
       }},
      {"daz_genesis", "daz_genesis",
       [] {
         return renaming({"hip", "abdomenLower", "abdomenUpper", "chestUpper", "neckLower",
                          "neckUpper", "head"},
                         {"", "*ThighBend", "*Shin", "*Foot", "*Toe", "*Collar", "*ShldrBend",
                          "*ForearmBend", "*Hand", "*Carpal1", "*Index1", "*Thumb1"},
                         "l", "r");
       }},
      {"makehuman", "makehuman",
       [] {
         return renaming({"root", "spine05", "spine04", "spine03", "neck01", "neck02", "head"},
                         {"pelvis.*", "upperleg01.*", "lowerleg01.*", "foot.*", "toe1-1.*",
                          "clavicle.*", "upperarm01.*", "lowerarm01.*", "wrist.*", "finger2-1.*",
                          "finger2-2.*", "finger1-1.*"},
                         "L", "R");
       }},
  };
}

// Every joint renamed by `renaming`; the ones it leaves out become "extra_<index>".
Skeleton renamed(Skeleton skeleton, const Renaming& renaming) {
  for (int j = 0; j < skeleton.size(); ++j) {
    const auto it = renaming.find(skeleton.joints[j].name);
    skeleton.joints[j].name = it != renaming.end() ? it->second : "extra_" + std::to_string(j);
  }
  return skeleton;
}

Skeleton with_names(Skeleton skeleton,
                    const std::function<std::string(int, const std::string&)>& name) {
  for (int j = 0; j < skeleton.size(); ++j)
    skeleton.joints[j].name = name(j, skeleton.joints[j].name);
  return skeleton;
}

struct SharedSkeleton {
  std::string label;
  Skeleton skeleton;
};

// The male's skeleton (when the shared data is there) and the mannequin's, made once.
const std::vector<SharedSkeleton>& shared_skeletons() {
  static const std::vector<SharedSkeleton> skeletons = [] {
    std::vector<SharedSkeleton> found;
    const fs::path male = fs::path(SWEEPD_SHARED_DATA) / "models/makehuman_male_cmu.glb";
    if (fs::exists(male)) found.push_back({"male", io::load_gltf(male).skeleton});
    found.push_back({"mannequin", mannequin::make_mannequin({.target_vertices = 2000}).skeleton});
    return found;
  }();
  return skeletons;
}

TEST(RigMapRenamedModels, EveryConventionMapsTheSameJointsAsTheCmuNames) {
  for (const SharedSkeleton& shared : shared_skeletons()) {
    const RigMap original = detect_rig_map(shared.skeleton);
    ASSERT_EQ(original.convention, "cmu_motionbuilder");
    for (const Convention& convention : conventions()) {
      SCOPED_TRACE(shared.label + " as " + convention.test_name);
      const Skeleton skeleton = renamed(shared.skeleton, convention.renaming());
      const RigMap map = detect_rig_map(skeleton);
      EXPECT_EQ(map.convention, convention.name);
      test::expect_same_rig_parts(map, original);
      for (const PartDetection& found : map.found)
        EXPECT_EQ(found.finding, PartFinding::kByName) << found.note;
      EXPECT_TRUE(map.warnings.empty());
    }
  }
}

TEST(RigMapRenamedModels, NamespacesPipesAndSuffixesAreIgnored) {
  for (const SharedSkeleton& shared : shared_skeletons()) {
    SCOPED_TRACE(shared.label);
    const RigMap original = detect_rig_map(shared.skeleton);
    const Skeleton skeleton = with_names(shared.skeleton, [](int, const std::string& name) {
      return "Armature|body|ns:" + name + ".001";
    });
    const RigMap map = detect_rig_map(skeleton);
    EXPECT_EQ(map.convention, "cmu_motionbuilder");
    test::expect_same_rig_parts(map, original);
  }
}

TEST(RigMapRenamedModels, MeaninglessNamesMapByShapeToTheSameParts) {
  for (const SharedSkeleton& shared : shared_skeletons()) {
    SCOPED_TRACE(shared.label);
    const RigMap original = detect_rig_map(shared.skeleton);
    const Skeleton skeleton = with_names(
        shared.skeleton, [](int j, const std::string&) { return "j" + std::to_string(j); });
    const RigMap map = detect_rig_map(skeleton);
    EXPECT_EQ(map.convention, "topological");
    test::expect_same_rig_parts(map, original);
    for (const PartDetection& found : map.found) EXPECT_EQ(found.finding, PartFinding::kByShape);
    EXPECT_TRUE(map.warnings.empty());
  }
}

std::vector<glm::vec3> posed_by_sweeps(const Model& model) {
  const RigMap rig = detect_rig_map(model.skeleton);
  const BoundModel bound = bind(model, rig);
  test::Posing posing(bound);
  return test::deformed(posing, test::swept_parts_pose(model.skeleton, rig), DeformMethod::kSweep);
}

float largest_distance(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  float largest = 0.0f;
  for (std::size_t v = 0; v < a.size(); ++v) largest = std::max(largest, glm::distance(a[v], b[v]));
  return largest;
}

TEST(RigMapRenamedModels, RenamedMannequinPosesLikeTheOriginal) {
  // Renaming changes no joint id, so the same parts must give the same vertices; 1e-5 m is the
  // issue's bound (the binding is deterministic: in practice they are equal).
  const Model original = mannequin::make_mannequin({.target_vertices = 3000});
  const std::vector<glm::vec3> expected = posed_by_sweeps(original);
  const std::vector<Convention> all = conventions();
  const std::vector<std::pair<std::string, Renaming>> variants = {
      {"rigify", all[2].renaming()}, {"unreal", all[1].renaming()}, {"daz", all[7].renaming()}};
  for (const auto& [label, renaming] : variants) {
    SCOPED_TRACE(label);
    Model model = original;
    model.skeleton = renamed(original.skeleton, renaming);
    EXPECT_LE(largest_distance(posed_by_sweeps(model), expected), 1e-5f);
  }
  Model nonsense = original;
  nonsense.skeleton = with_names(original.skeleton,
                                 [](int j, const std::string&) { return "j" + std::to_string(j); });
  EXPECT_LE(largest_distance(posed_by_sweeps(nonsense), expected), 1e-5f) << "nonsense names";
}

TEST(RigMapRenamedModels, RigifyAndNonsenseNamedMalePoseLikeTheOriginal) {
  REQUIRE_SHARED_MALE();
  const std::vector<glm::vec3> expected = posed_by_sweeps(male.model);
  for (const bool rigify : {true, false}) {
    SCOPED_TRACE(rigify ? "rigify metarig names" : "nonsense names");
    Model model = male.model;
    model.skeleton = rigify ? renamed(male.model.skeleton, conventions()[2].renaming())
                            : with_names(male.model.skeleton, [](int j, const std::string&) {
                                return "j" + std::to_string(j);
                              });
    EXPECT_LE(largest_distance(posed_by_sweeps(model), expected), 1e-5f);
  }
}

}  // namespace
}  // namespace sweepd::deform
