// client_examples/stream_poses.py (the Python example on the sweepd-client package, Debian's
// /usr/bin/python3) against the real daemon: a CMU clip, kept and retargeted on the server, is
// answered pose for pose over TCP and a Unix socket, onto the mannequin and onto an uploaded
// male with Unreal joint names; a wrong token, an unknown model, a bad BVH file and an
// unreachable server end it with their own exit code and reason.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <fstream>
#include <map>

#include "io/gltf/gltf_load.h"
#include "io/gltf/gltf_save.h"
#include "tests/server/client_run.h"
#include "tests/server/daemon_process.h"

namespace sweepd::test::stream_poses_py_test {
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
    if (std::system(
            (std::string(kPython) + " -c 'import flatbuffers, numpy' 2>/dev/null").c_str()) != 0) {
      GTEST_SKIP() << kPython << " with python3-flatbuffers and python3-numpy is not installed";
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
  // Where the server is.
  std::string server_arguments(const std::string& token = kToken) const {
    return "--port " + std::to_string(daemon_->port()) + " --token " + token;
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
  // The token from a file (its first line), as a mounted Secret gives it.
  const fs::path token_file = directory_ / "token";
  std::ofstream(token_file) << kToken << "\n";
  const ClientRun run = run_script(
      "--unix " + (directory_ / "sweepd.sock").string() + " --token-file " + token_file.string() +
      " --bvh " + clip("cmu_01_03") + " --frames 120 --flat-out --latest-wins --float16");
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
  const ClientRun unreachable =
      run_script("--port " + std::to_string(ntohs(address.sin_port)) + bvh);
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

// The server retargets: an uploaded body whose joints carry Unreal names is driven by a CMU
// clip (matched by rig role and hierarchy on the server), answered pose for pose.
TEST_F(StreamPosesPy, DrivesAnUploadedBodyWithUnrealNamesThroughTheServersRetargeting) {
  const fs::path male = data_ / "models/makehuman_male_cmu.glb";
  ASSERT_TRUE(fs::exists(male)) << male;
  const fs::path male_unreal = save_male_with_unreal_names(male, directory_);
  const ClientRun run = run_script(server_arguments() + " --bvh " + clip("cmu_01_03") +
                                   " --flat-out --frames 12 --first-frame 3200 --model male_unreal"
                                   " --model-file " +
                                   male_unreal.string());
  ASSERT_EQ(run.exit_code, 0) << run.output << daemon_->log();
  EXPECT_EQ(pose_counts(run.output), (std::array<int, 4>{12, 12, 0, 0})) << run.output;
  EXPECT_NE(run.output.find("14517 vertices"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace sweepd::test::stream_poses_py_test
