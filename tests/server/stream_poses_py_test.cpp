// client_examples/stream_poses.py (the Python client, Debian's /usr/bin/python3 with
// python3-flatbuffers) against the real daemon: a CMU clip is answered pose for pose over TCP
// and a Unix socket; a wrong token, an unknown model, a bad BVH file and an unreachable server
// end it with their own exit code and reason; and its retargeting (--dump-poses) equals the C++
// library's (client::retarget_onto) on the default mannequin and on the uploaded shared male,
// with its own CMU joint names and with Unreal ones.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "client/connection.h"
#include "client/model_skeleton.h"
#include "io/bvh_load.h"
#include "io/gltf_load.h"
#include "io/gltf_save.h"
#include "tests/server/client_run.h"
#include "tests/server/daemon_process.h"

namespace sweepd::test {
namespace {

constexpr char kPython[] = "/usr/bin/python3";
constexpr char kToken[] = "t0k";
// The script's exit codes (see its top).
constexpr int kExitBadInput = 2, kExitConnection = 3, kExitRefused = 4;

// Runs the script with `arguments`; `environment` is prefixed to the command ("NAME=value ").
ClientRun run_script(const std::string& arguments, const std::string& environment = {}) {
  return run_client(environment + kPython + " " + SWEEPD_SOURCE_DIR +
                    "/client_examples/stream_poses.py " + arguments);
}

class StreamPosesPy : public ::testing::Test {
 protected:
  void SetUp() override {
    if (std::system((std::string(kPython) + " -c 'import flatbuffers' 2>/dev/null").c_str()) != 0) {
      GTEST_SKIP() << kPython << " with python3-flatbuffers is not installed";
    }
    data_ = SWEEPD_SHARED_DATA;
    if (!fs::exists(data_ / "motion/cmu_01_01.bvh")) GTEST_SKIP() << "shared data absent";
    directory_ = fresh_directory("stream_poses_py");
    daemon_ = std::make_unique<DaemonProcess>(
        directory_, std::vector<std::string>{"--token", kToken, "--unix-socket",
                                             (directory_ / "sweepd.sock").string()});
    ASSERT_TRUE(daemon_->running()) << daemon_->log();
  }
  void TearDown() override {
    daemon_.reset();
    if (!directory_.empty()) fs::remove_all(directory_);
  }
  // Where the server is and where the generated protocol package is.
  std::string server_arguments(const std::string& token = kToken) const {
    return "--port " + std::to_string(daemon_->port()) + " --token " + token + " --protocol-dir " +
           SWEEPD_PROTOCOL_PYTHON_DIR;
  }
  std::string clip(const std::string& name) const {
    return (data_ / "motion" / (name + ".bvh")).string();
  }

  fs::path data_, directory_;
  std::unique_ptr<DaemonProcess> daemon_;
};

TEST_F(StreamPosesPy, InOrderClipIsAnsweredPoseForPose) {
  const ClientRun run =
      run_script(server_arguments() + " --bvh " + clip("cmu_01_01") + " --frames 60 --flat-out");
  ASSERT_EQ(run.exit_code, 0) << run.output << daemon_->log();
  EXPECT_EQ(pose_counts(run.output), (std::array<int, 4>{60, 60, 0, 0})) << run.output;
  EXPECT_NE(run.output.find("round trip ms: p50"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("server deformation ms: p50"), std::string::npos) << run.output;
}

TEST_F(StreamPosesPy, LatestWinsOverAUnixSocketAnswersOrCountsEveryPose) {
  // The package found through the environment variable instead of --protocol-dir; the token
  // from a file (its first line), as a mounted Secret gives it.
  const fs::path token_file = directory_ / "token";
  std::ofstream(token_file) << kToken << "\n";
  const ClientRun run = run_script(
      "--unix " + (directory_ / "sweepd.sock").string() + " --token-file " + token_file.string() +
          " --bvh " + clip("cmu_01_03") + " --frames 120 --flat-out --latest-wins --float16",
      std::string("SWEEPD_PROTOCOL_PYTHON=") + SWEEPD_PROTOCOL_PYTHON_DIR + " ");
  ASSERT_EQ(run.exit_code, 0) << run.output << daemon_->log();
  const std::array<int, 4> counts = pose_counts(run.output);
  EXPECT_EQ(counts[0], 120) << run.output;
  EXPECT_EQ(counts[1] + counts[2], 120) << run.output;
  EXPECT_GE(counts[1], 1) << "the newest pose is always answered";
  EXPECT_EQ(counts[3], 0) << run.output;
}

TEST_F(StreamPosesPy, RefusalsAndBadInputEndTheScriptWithTheirReason) {
  const std::string bvh = " --bvh " + clip("cmu_01_01") + " --frames 5";
  const ClientRun wrong_token = run_script(server_arguments("wrong") + bvh);
  EXPECT_EQ(wrong_token.exit_code, kExitRefused) << wrong_token.output;
  EXPECT_NE(wrong_token.output.find("AuthFailed"), std::string::npos) << wrong_token.output;

  const ClientRun unknown_model = run_script(server_arguments() + bvh + " --model no_such_body");
  EXPECT_EQ(unknown_model.exit_code, kExitRefused) << unknown_model.output;
  EXPECT_NE(unknown_model.output.find("UnknownModel: model 'no_such_body'"), std::string::npos)
      << unknown_model.output;

  const fs::path broken = directory_ / "broken.bvh";
  std::ofstream(broken) << "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0\n}\n";
  const ClientRun bad_bvh = run_script(server_arguments() + " --bvh " + broken.string());
  EXPECT_EQ(bad_bvh.exit_code, kExitBadInput) << bad_bvh.output;
  EXPECT_NE(bad_bvh.output.find(broken.string() + ":5: OFFSET"), std::string::npos)
      << bad_bvh.output;

  // A port nobody listens on: bound, then closed again.
  const int probe = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t size = sizeof(address);
  ASSERT_EQ(bind(probe, reinterpret_cast<sockaddr*>(&address), size), 0);
  ASSERT_EQ(getsockname(probe, reinterpret_cast<sockaddr*>(&address), &size), 0);
  close(probe);
  const ClientRun unreachable = run_script("--port " + std::to_string(ntohs(address.sin_port)) +
                                           " --protocol-dir " + SWEEPD_PROTOCOL_PYTHON_DIR + bvh);
  EXPECT_EQ(unreachable.exit_code, kExitConnection) << unreachable.output;
  EXPECT_NE(unreachable.output.find("cannot connect"), std::string::npos) << unreachable.output;
}

// The shared male with Unreal joint names (pelvis, thigh_l, upperarm_l, ...; the joints
// Unreal has no role for get names of their own), so a CMU clip drives it by rig role and
// hierarchy, not by name. Written as a .glb under `directory`.
fs::path save_male_with_unreal_names(const fs::path& male, const fs::path& directory) {
  const std::map<std::string, std::string> unreal = {
      {"Hips", "pelvis"},        {"LowerBack", "spine_01"}, {"Spine", "spine_02"},
      {"Spine1", "spine_03"},    {"Neck", "neck_01"},       {"Neck1", "neck_02"},
      {"Head", "head"},          {"HipJoint", "hip_link_"}, {"UpLeg", "thigh_"},
      {"Leg", "calf_"},          {"Foot", "foot_"},         {"ToeBase", "ball_"},
      {"Shoulder", "clavicle_"}, {"Arm", "upperarm_"},      {"ForeArm", "lowerarm_"},
      {"Hand", "hand_"},         {"FingerBase", "palm_"},   {"HandFinger1", "fingers_"},
      {"Thumb", "thumb_"}};
  deform::Model model = io::load_gltf(male);
  for (deform::Joint& joint : model.skeleton.joints) {
    std::string name = joint.name, side;
    for (const std::string prefix : {"Left", "Right", "L", "R"}) {
      if (name.starts_with(prefix) && unreal.contains(name.substr(prefix.size()))) {
        side = prefix.substr(0, 1) == "L" ? "l" : "r";
        name = name.substr(prefix.size());
        break;
      }
    }
    joint.name = unreal.at(name) + side;
  }
  const fs::path file = directory / "male_unreal.glb";
  io::save_gltf(model, file);
  return file;
}

// The poses the script sent (--dump-poses) against client::retarget_onto for the same
// ModelInfo and clip. Python computes in double from the file's text, C++ in float (values
// rounded to float, ~10 quaternion products per joint): they differ by less than 1e-6, so
// 1e-4 per quaternion component leaves margin yet catches a wrong match or alignment (those
// move components by > 1e-2). The root translation (~1 m, float) gets 1e-5 m: the mannequin's
// hip-height ratio is close to 1, and leaving it out moves the root by only ~1e-4 m.
TEST_F(StreamPosesPy, RetargetsLikeTheCppLibrary) {
  constexpr double kTolerance = 1e-4, kRootTolerance = 1e-5;
  const fs::path male = data_ / "models/makehuman_male_cmu.glb";
  ASSERT_TRUE(fs::exists(male)) << male;
  const fs::path male_unreal = save_male_with_unreal_names(male, directory_);
  struct Case {
    std::string clip;
    int first_frame;
    std::string model;  // its name on the server
    fs::path upload;    // the .glb the script uploads; empty: the default mannequin
  };
  for (const Case& c :
       {Case{"cmu_01_01", 700, "mannequin", {}}, Case{"cmu_01_03", 2000, "mannequin", {}},
        Case{"cmu_01_01", 1500, "male", male},
        Case{"cmu_01_03", 3200, "male_unreal", male_unreal}}) {
    SCOPED_TRACE(c.clip + " on " + c.model);
    const fs::path dump = directory_ / "poses.jsonl";
    const ClientRun run = run_script(
        server_arguments() + " --bvh " + clip(c.clip) + " --flat-out --frames 12 --first-frame " +
        std::to_string(c.first_frame) + " --dump-poses " + dump.string() + " --model " + c.model +
        (c.upload.empty() ? std::string() : " --model-file " + c.upload.string()));
    ASSERT_EQ(run.exit_code, 0) << run.output << daemon_->log();

    // The model as the server holds it (the upload is loaded under its name by now).
    client::Connection connection("127.0.0.1", std::to_string(daemon_->port()));
    connection.hello(kToken, "stream_poses_py_test");
    const protocol::ModelInfo& info = connection.load_model(c.model);
    const motion::Retargeter expected =
        client::retarget_onto(info, io::load_bvh(clip(c.clip), {.length_scale = 0.056444f}));
    if (c.model == "male_unreal") {
      const auto by_role = std::count_if(
          expected.matches().begin(), expected.matches().end(),
          [](const motion::JointMatch& m) { return m.reason == motion::JointMatchReason::kRole; });
      EXPECT_GE(by_role, 10) << "the Unreal names are matched by role";
    }

    std::ifstream lines(dump);
    int compared = 0;
    for (std::string line; std::getline(lines, line); ++compared) {
      const nlohmann::json pose = nlohmann::json::parse(line);
      const int frame = pose.at("frame");
      EXPECT_EQ(frame, c.first_frame + compared);
      const deform::Pose want = expected.pose_at_frame(frame);
      const auto& rotations = pose.at("rotations");
      ASSERT_EQ(rotations.size(), want.local_rotations.size());
      for (std::size_t j = 0; j < rotations.size(); ++j) {
        const glm::quat& q = want.local_rotations[j];
        const std::array<float, 4> xyzw = {q.x, q.y, q.z, q.w};
        for (int k = 0; k < 4; ++k)
          EXPECT_NEAR(rotations[j][k].get<double>(), xyzw[k], kTolerance)
              << "frame " << frame << " joint " << j << " component " << k;
      }
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(pose.at("root_translation")[k].get<double>(), want.root_translation[k],
                    kRootTolerance)
            << "frame " << frame << " root axis " << k;
    }
    EXPECT_EQ(compared, 12);
  }
}

}  // namespace
}  // namespace sweepd::test
