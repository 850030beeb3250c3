#include "io/json/rig_map_json.h"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>

#include "io/files/load_error.h"
#include "tests/deform/rig/same_rig_parts.h"
#include "tests/deform/synthetic_humanoid.h"
#include "tests/scratch_directory.h"

namespace sweepd::io {
namespace {

using deform::RigMap;
using nlohmann::json;

std::filesystem::path temp_file(const std::string& name) {
  return sweepd::test::process_scratch("rig_map_json") / name;
}

void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

class RigMapJsonTest : public ::testing::Test {
 protected:
  const deform::Skeleton skeleton = test::make_humanoid(test::cmu_motionbuilder_spec());
  const RigMap detected = deform::detect_rig_map(skeleton);

  // The detected map as the JSON document save_rig_map_json writes.
  json saved_document(const std::string& name) {
    const std::filesystem::path path = temp_file(name);
    save_rig_map_json(detected, skeleton, path);
    return json::parse(std::ifstream(path));
  }

  // The LoadError message for loading `text`; checks it names the file.
  std::string load_error(const std::string& name, const std::string& text) {
    const std::filesystem::path path = temp_file(name);
    write_text(path, text);
    try {
      load_rig_map_json(path, skeleton);
    } catch (const LoadError& e) {
      EXPECT_EQ(e.file(), path);
      EXPECT_EQ(std::string(e.what()).rfind(path.string() + ": ", 0), 0u) << e.what();
      return e.what();
    }
    return "(no error)";
  }
};

TEST_F(RigMapJsonTest, RoundTripKeepsEveryRole) {
  const std::filesystem::path path = temp_file("round_trip.json");
  save_rig_map_json(detected, skeleton, path);
  const RigMap loaded = load_rig_map_json(path, skeleton);
  EXPECT_EQ(loaded.convention, "json");
  deform::test::expect_same_rig_parts(loaded, detected);
  ASSERT_GE(detected.left_leg.hip, 0) << "the round trip should carry the optional roles";
}

TEST_F(RigMapJsonTest, RoundTripWithoutOptionalRoles) {
  RigMap map = detected;
  map.left_arm.clavicle = map.right_arm.clavicle = -1;
  map.left_leg.hip = map.left_leg.toe = map.right_leg.hip = map.right_leg.toe = -1;
  const std::filesystem::path path = temp_file("no_optional.json");
  save_rig_map_json(map, skeleton, path);
  const json written = json::parse(std::ifstream(path));
  EXPECT_FALSE(written["left_arm"].contains("clavicle"));
  deform::test::expect_same_rig_parts(load_rig_map_json(path, skeleton), map);
}

TEST_F(RigMapJsonTest, AbsentLegsAndHeadRoundTripAsNull) {
  // A map with parts the body lacks (as detect_rig_map leaves them) writes them as null and
  // reads them back absent.
  RigMap map = detected;
  map.left_leg = {};
  map.right_leg = {};
  map.neck = {};
  const std::filesystem::path path = temp_file("absent_parts.json");
  save_rig_map_json(map, skeleton, path);
  const json written = json::parse(std::ifstream(path));
  EXPECT_TRUE(written["left_leg"].is_null());
  EXPECT_TRUE(written["neck"].is_null());
  const RigMap loaded = load_rig_map_json(path, skeleton);
  EXPECT_TRUE(loaded.left_leg.absent() && loaded.right_leg.absent());
  EXPECT_FALSE(loaded.has_head());
  deform::test::expect_same_rig_parts(loaded, map);
}

TEST_F(RigMapJsonTest, WritesJointNamesByRole) {
  const json document = saved_document("names.json");
  EXPECT_EQ(document["torso"], json({"Hips", "LowerBack", "Spine", "Spine1"}));
  EXPECT_EQ(document["neck"], json({"Neck", "Neck1", "Head"}));
  EXPECT_EQ(document["left_arm"]["upper"], "LeftArm");
  EXPECT_EQ(document["right_leg"]["hip"], "RHipJoint");
  EXPECT_EQ(document["convention"], "cmu_motionbuilder");
}

TEST_F(RigMapJsonTest, AcceptsLimbsAsArraysInChainOrder) {
  json document = saved_document("arrays_base.json");
  document["left_arm"] = {"LeftArm", "LeftForeArm", "LeftHand"};
  document["right_arm"] = {"RightShoulder", "RightArm", "RightForeArm", "RightHand"};
  document["left_leg"] = {"LHipJoint", "LeftUpLeg", "LeftLeg", "LeftFoot", "LeftToeBase"};
  document["right_leg"] = {"RightUpLeg", "RightLeg", "RightFoot"};
  const std::filesystem::path path = temp_file("arrays.json");
  write_text(path, document.dump());
  const RigMap map = load_rig_map_json(path, skeleton);
  EXPECT_EQ(map.left_arm.clavicle, -1);
  EXPECT_EQ(map.left_arm.upper, skeleton.find("LeftArm"));
  EXPECT_EQ(map.right_arm.clavicle, skeleton.find("RightShoulder"));
  EXPECT_EQ(map.left_leg.toe, skeleton.find("LeftToeBase"));
  EXPECT_EQ(map.right_leg.hip, -1);
  EXPECT_EQ(map.right_leg.foot, skeleton.find("RightFoot"));
}

TEST_F(RigMapJsonTest, ErrorsNameTheFileAndTheProblem) {
  const json base = saved_document("errors_base.json");
  struct Case {
    std::string name;
    std::function<void(json&)> edit;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {"unknown_joint", [](json& d) { d["left_arm"]["hand"] = "LeftHnd"; },
       "left_arm.hand: no joint named 'LeftHnd' in the skeleton"},
      {"torso_not_a_chain",
       [](json& d) {
         d["torso"] = {"Hips", "Spine", "LowerBack", "Spine1"};
       },
       "torso: 'Spine' is not a child of 'Hips'"},
      {"arm_roles_swapped",
       [](json& d) {
         d["left_arm"]["upper"] = "LeftForeArm";
         d["left_arm"]["lower"] = "LeftArm";
       },
       "left arm: 'LeftArm' is not below 'LeftForeArm'"},
      {"joint_used_twice", [](json& d) { d["left_arm"]["clavicle"] = "Spine1"; },
       "left arm: joint 'Spine1' is already used by the torso"},
      {"missing_part", [](json& d) { d.erase("right_leg"); }, "missing part \"right_leg\""},
      {"unknown_part", [](json& d) { d["lef_arm"] = d["left_arm"]; }, "unknown key \"lef_arm\""},
      {"unknown_role", [](json& d) { d["left_arm"]["elbow"] = "LeftForeArm"; },
       "left_arm: unknown role \"elbow\""},
      {"missing_role", [](json& d) { d["left_leg"].erase("foot"); },
       "left_leg: missing role \"foot\""},
      {"ambiguous_leg_array",
       [](json& d) {
         d["left_leg"] = {"LeftUpLeg", "LeftLeg", "LeftFoot", "LeftToeBase"};
       },
       "left_leg: an array must list 3 or 5 joint names, has 4"},
      {"number_for_name",
       [](json& d) {
         d["neck"] = {"Neck", 5};
       },
       "neck[1]: expected a joint name (a string), got 5"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    json document = base;
    c.edit(document);
    const std::string error = load_error(c.name + ".json", document.dump(2));
    EXPECT_NE(error.find(c.expected), std::string::npos) << error;
  }
}

TEST_F(RigMapJsonTest, NotJsonAndMissingFileAreLoadErrors) {
  EXPECT_NE(load_error("broken.json", "{\"torso\": [\"Hips\",").find("not valid JSON"),
            std::string::npos);
  EXPECT_NE(load_error("list.json", "[1, 2]").find("expected a JSON object"), std::string::npos);
  const std::filesystem::path missing = temp_file("does_not_exist.json");
  std::filesystem::remove(missing);
  try {
    load_rig_map_json(missing, skeleton);
    ADD_FAILURE() << "loading a missing file should throw";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos) << e.what();
    EXPECT_EQ(e.file(), missing);
  }
}

}  // namespace
}  // namespace sweepd::io
