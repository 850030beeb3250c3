// Tests for io::load_pose_json / io::save_pose_json (the hand-written pose format).
#include "io/json/pose_json.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "io/files/load_error.h"
#include "tests/deform/synthetic_humanoid.h"

namespace sweepd::io {
namespace {

namespace fs = std::filesystem;

// The CMU-named synthetic humanoid, with a rest rotation on LeftForeArm so that "keeps its rest
// rotation" and "replaced" can be told apart.
deform::Skeleton humanoid() {
  deform::Skeleton skeleton = test::make_humanoid(test::cmu_motionbuilder_spec());
  skeleton.joints[skeleton.find("LeftForeArm")].rest_rotation =
      glm::angleAxis(0.25f, glm::vec3(0, 0, 1));
  return skeleton;
}

// A file of its own per test, removed afterwards.
class PoseFile {
 public:
  PoseFile()
      : path_(fs::temp_directory_path() /
              ("sweepd_pose_" + std::to_string(::getpid()) + "_" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".json")) {}
  explicit PoseFile(const std::string& text) : PoseFile() { std::ofstream(path_) << text; }
  ~PoseFile() { fs::remove(path_); }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

TEST(PoseJson, HandWrittenRotationsReplaceListedJointsOnly) {
  const deform::Skeleton skeleton = humanoid();
  const PoseFile file(R"({
    "root_translation": [0.5, 1.0, -0.25],
    "rotations": {
      "LeftArm": {"axis": [2, 0, 0], "degrees": 90},
      "Neck": [2, 0, 0, 0]
    }
  })");
  const deform::Pose pose = load_pose_json(file.path(), skeleton);
  EXPECT_EQ(pose.root_translation, glm::vec3(0.5f, 1.0f, -0.25f));  // exact binary fractions
  // 90° about +X from a non-unit axis: float sin/cos of pi/4, a few ulps.
  const glm::quat expected = glm::angleAxis(std::numbers::pi_v<float> / 2, glm::vec3(1, 0, 0));
  const glm::quat arm = pose.local_rotations[skeleton.find("LeftArm")];
  EXPECT_NEAR(std::abs(glm::dot(arm, expected)), 1.0f, 1e-6f);
  // [2, 0, 0, 0] is the identity once normalised (exactly: 2 / 2).
  EXPECT_EQ(pose.local_rotations[skeleton.find("Neck")], glm::identity<glm::quat>());
  // Unlisted joints keep their rest rotation, bit for bit.
  const int forearm = skeleton.find("LeftForeArm");
  EXPECT_EQ(pose.local_rotations[forearm], skeleton.joints[forearm].rest_rotation);
}

TEST(PoseJson, EmptyObjectIsTheRestPose) {
  const deform::Skeleton skeleton = humanoid();
  const PoseFile file("{}");
  const deform::Pose pose = load_pose_json(file.path(), skeleton);
  const deform::Pose rest = deform::rest_pose(skeleton);
  EXPECT_EQ(pose.root_translation, rest.root_translation);
  EXPECT_EQ(pose.local_rotations, rest.local_rotations);
}

TEST(PoseJson, SaveThenLoadGivesThePoseBackExactly) {
  const deform::Skeleton skeleton = humanoid();
  deform::Pose pose = deform::rest_pose(skeleton);
  pose.root_translation = {0.123456789f, 0.98765f, -1e-7f};
  for (int j = 0; j < skeleton.size(); j += 3)
    pose.local_rotations[j] =
        glm::angleAxis(0.1f * static_cast<float>(j + 1), glm::normalize(glm::vec3(1, j, -2)));
  const PoseFile file;
  save_pose_json(pose, skeleton, file.path());
  const deform::Pose loaded = load_pose_json(file.path(), skeleton);
  // Floats are written with enough digits to round-trip and unit quaternions are not
  // renormalised on load: equality to the last bit.
  EXPECT_EQ(loaded.root_translation, pose.root_translation);
  for (int j = 0; j < skeleton.size(); ++j)
    EXPECT_EQ(loaded.local_rotations[j], pose.local_rotations[j]) << skeleton.joints[j].name;
}

TEST(PoseJson, SaveRefusesAPoseThatDoesNotFit) {
  const deform::Skeleton skeleton = humanoid();
  deform::Pose pose = deform::rest_pose(skeleton);
  pose.local_rotations.pop_back();
  const PoseFile file;
  EXPECT_THROW(save_pose_json(pose, skeleton, file.path()), std::invalid_argument);
  EXPECT_THROW(save_pose_json(deform::rest_pose(skeleton), skeleton, "/nonexistent/dir/p.json"),
               std::runtime_error);
}

TEST(PoseJson, ErrorsNameTheFileAndTheProblem) {
  const deform::Skeleton skeleton = humanoid();
  const std::pair<const char*, const char*> cases[] = {
      {R"({"rotations": {"LeftElbow": [1, 0, 0, 0]}})", "no joint named 'LeftElbow'"},
      {R"({"rotations": {"Neck": [1, 0, 0]}})", "rotations.Neck: expected an array of 4"},
      {R"({"rotations": {"Neck": [1, "a", 0, 0]}})", "rotations.Neck: element 1"},
      {R"({"rotations": {"Neck": [0, 0, 0, 0]}})", "rotations.Neck: the quaternion has zero"},
      {R"({"rotations": {"Neck": [1e39, 0, 0, 0]}})", "NaN or infinite"},
      {R"({"rotations": {"Neck": {"axis": [0, 0, 0], "degrees": 5}}})", "axis has zero length"},
      {R"({"rotations": {"Neck": {"axis": [1, 0, 0]}}})", "needs both"},
      {R"({"rotations": {"Neck": {"axis": [1, 0, 0], "degrees": "x"}}})", "degrees"},
      {R"({"rotations": {"Neck": {"axis": [1, 0, 0], "degrees": 5, "turns": 1}}})", "turns"},
      {R"({"rotations": {"Neck": "up"}})", "rotations.Neck"},
      {R"({"root_translation": [0, 1]})", "root_translation"},
      {R"({"rotation": {}})", "unknown key \"rotation\""},
      {R"({"rotations": []})", "\"rotations\" must be an object"},
      {R"([1, 2])", "expected a JSON object"},
      {R"({"rotations": )", "not valid JSON"}};
  for (const auto& [text, expected] : cases) {
    const PoseFile file(text);
    try {
      load_pose_json(file.path(), skeleton);
      ADD_FAILURE() << "no error for " << text;
    } catch (const LoadError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(file.path().filename().string()), std::string::npos) << message;
      EXPECT_NE(message.find(expected), std::string::npos) << message;
    }
  }
  EXPECT_THROW(load_pose_json("/nonexistent/pose.json", skeleton), LoadError);
}

}  // namespace
}  // namespace sweepd::io
