// client_examples/stream_poses against the real daemon: a CMU clip streamed InOrder is
// answered pose for pose; streamed LatestWins every pose is answered or counted as dropped; a
// glTF file's animation (--clip-from, --clip; protocol 1.7) streams like a BVH; a clip streamed
// on the Unix socket with replies in shared memory (1.10) is answered pose for pose; an unknown
// animation name ends the client naming the file's animations; the model's range of motion
// (--range-of-motion, 1.13) streams with no clip file; a daemon restarted on an empty store
// mid-stream gets the model uploaded again and every pose is answered once.
#include <gtest/gtest.h>

#include <array>
#include <future>

#include "io/gltf/gltf_load.h"
#include "io/gltf/gltf_save.h"
#include "mannequin/mannequin.h"
#include "tests/io/baked_gltf_clip.h"
#include "tests/server/client_run.h"
#include "tests/server/daemon_process.h"

namespace sweepd::test::stream_poses_test {
namespace {

ClientRun run_stream_poses(const std::string& arguments) {
  return run_client(std::string(SWEEPD_STREAM_POSES) + " " + arguments);
}

class StreamPoses : public ClipClientTest {
 protected:
  StreamPoses() : ClipClientTest("stream_poses") {}
  std::string common_arguments() const {
    return "--port " + std::to_string(daemon_->port()) + " --token t0k --bvh " + clip_.string();
  }
};

TEST_F(StreamPoses, InOrderClipIsAnsweredPoseForPose) {
  const ClientRun run = run_stream_poses(common_arguments() + " --frames 90 --flat-out");
  ASSERT_EQ(run.exit_code, 0) << run.output << daemon_->log();
  EXPECT_EQ(pose_counts(run.output), (std::array<int, 4>{90, 90, 0, 0})) << run.output;
  EXPECT_NE(run.output.find("round trip ms: p50"), std::string::npos) << run.output;
}

TEST_F(StreamPoses, LatestWinsAnswersOrCountsEveryPose) {
  const ClientRun run =
      run_stream_poses(common_arguments() + " --frames 300 --flat-out --latest-wins --float16");
  ASSERT_EQ(run.exit_code, 0) << run.output << daemon_->log();
  const std::array<int, 4> counts = pose_counts(run.output);
  EXPECT_EQ(counts[0], 300);
  EXPECT_EQ(counts[1] + counts[2], 300) << run.output;
  EXPECT_GE(counts[1], 1) << "the newest pose is always answered";
  EXPECT_EQ(counts[3], 0) << run.output;
}

TEST_F(StreamPoses, SharedMemoryOnTheUnixSocketIsAnsweredPoseForPose) {
  // A daemon of its own with a Unix socket (the fixture's listens on TCP only).
  const fs::path directory = fresh_directory("stream_poses_unix");
  const fs::path socket = directory / "sweepd.sock";
  {
    DaemonProcess daemon(directory, {"--token", "t0k", "--unix-socket", socket.string()});
    ASSERT_TRUE(daemon.running()) << daemon.log();
    const ClientRun run =
        run_stream_poses("--unix " + socket.string() + " --shared-memory --token t0k --bvh " +
                         clip_.string() + " --frames 60 --flat-out");
    ASSERT_EQ(run.exit_code, 0) << run.output << daemon.log();
    EXPECT_EQ(pose_counts(run.output), (std::array<int, 4>{60, 60, 0, 0})) << run.output;
    EXPECT_NE(daemon.log().find("shared_memory_mapped"), std::string::npos) << daemon.log();
  }
  fs::remove_all(directory);
  // Shared memory needs the Unix socket, and float32: a bad command line naming the flag.
  for (const std::string flags : {" --shared-memory", " --unix /tmp/x --shared-memory --float16"}) {
    const ClientRun refused = run_stream_poses(common_arguments() + flags);
    EXPECT_EQ(refused.exit_code, 2) << refused.output;
    EXPECT_NE(refused.output.find("--shared-memory"), std::string::npos) << refused.output;
  }
}

TEST_F(StreamPoses, WrongTokenEndsTheClientWithTheServersReason) {
  const ClientRun run = run_stream_poses("--port " + std::to_string(daemon_->port()) +
                                         " --token wrong --bvh " + clip_.string());
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.output.find("AuthFailed"), std::string::npos) << run.output;
}

TEST_F(StreamPoses, AGltfAnimationStreamsLikeABvh) {
  // cmu_01_01 baked onto the shared male at 6 keys (tests/io/baked_gltf_clip.h).
  const deform::Model male =
      io::load_gltf(fs::path(SWEEPD_SHARED_DATA) / "models/makehuman_male_cmu.glb");
  const fs::path baked = directory_ / "baked.glb";
  io::testing::write_baked_gltf(male, io::testing::bake_cmu_clip(male, 6), baked);
  const std::string port = "--port " + std::to_string(daemon_->port()) + " --token t0k";
  const ClientRun run =
      run_stream_poses(port + " --clip-from " + baked.string() + " --clip cubic --flat-out");
  ASSERT_EQ(run.exit_code, 0) << run.output << daemon_->log();
  EXPECT_EQ(pose_counts(run.output), (std::array<int, 4>{6, 6, 0, 0})) << run.output;
  EXPECT_NE(run.output.find("clip baked.glb: 6 frames at 30 fps"), std::string::npos) << run.output;

  const ClientRun unknown =
      run_stream_poses(port + " --clip-from " + baked.string() + " --clip walk");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.output.find("ClipLoadFailed"), std::string::npos) << unknown.output;
  EXPECT_NE(unknown.output.find("0 'linear', 1 'step', 2 'cubic'"), std::string::npos)
      << unknown.output;
  const ClientRun both =
      run_stream_poses(port + " --bvh " + clip_.string() + " --clip-from " + baked.string());
  EXPECT_EQ(both.exit_code, 2) << both.output;
}

TEST_F(StreamPoses, TheModelsRangeOfMotionStreamsWithoutAClipFile) {
  const std::string port = "--port " + std::to_string(daemon_->port()) + " --token t0k";
  const ClientRun run = run_stream_poses(port + " --range-of-motion --frames 60 --flat-out");
  ASSERT_EQ(run.exit_code, 0) << run.output << daemon_->log();
  EXPECT_EQ(pose_counts(run.output), (std::array<int, 4>{60, 60, 0, 0})) << run.output;
  EXPECT_NE(run.output.find("clip range of motion: 1441 frames at 30 fps"), std::string::npos)
      << run.output;
  // A clip file besides is a usage error naming the flags.
  const ClientRun both = run_stream_poses(port + " --range-of-motion --bvh " + clip_.string());
  EXPECT_EQ(both.exit_code, 2) << both.output;
  EXPECT_NE(both.output.find("--range-of-motion"), std::string::npos) << both.output;
}

TEST_F(StreamPoses, ADaemonRestartedOnAnEmptyStoreMidStreamGetsTheModelAgain) {
  const fs::path glb = directory_ / "body.glb";
  io::save_gltf(mannequin::make_mannequin({.target_vertices = 2500}), glb);
  // 480 frames at the clip's 120 fps: 4 s, of which the first 0.3 s go to the first daemon.
  std::future<ClientRun> run = std::async(std::launch::async, [&] {
    return run_stream_poses(common_arguments() + " --model-file " + glb.string() + " --frames 480");
  });
  const std::string log = daemon_->log_with({"\"event\":\"clip_uploaded\""});
  ASSERT_NE(log.find("\"event\":\"clip_uploaded\""), std::string::npos) << log;
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ASSERT_EQ(run.wait_for(std::chrono::seconds(0)), std::future_status::timeout)
      << "the stream ended before the restart";
  const int port = daemon_->port();
  daemon_->signal(SIGKILL);
  ASSERT_TRUE(daemon_->wait().has_value());
  // Another store: the model's content id is unknown there (UnknownModel), as on a replica
  // without the shared volume.
  fs::create_directories(directory_ / "restarted");
  DaemonProcess restarted(
      directory_ / "restarted",
      {"--token", "t0k", "--port", std::to_string(port), "--mannequin-vertices", "1000"});
  ASSERT_TRUE(restarted.running()) << restarted.log();

  const ClientRun result = run.get();
  ASSERT_EQ(result.exit_code, 0) << result.output << restarted.log();
  EXPECT_EQ(pose_counts(result.output), (std::array<int, 4>{480, 480, 0, 0})) << result.output;
  EXPECT_NE(result.output.find("reconnected 1 times, model uploaded 2 times"), std::string::npos)
      << result.output;
  // The restarted daemon bound the upload (its start-up log names only the mannequin), under
  // the file's base name (issue 48: never the client's path).
  EXPECT_NE(restarted.model_id(glb.stem().string()), 0u) << restarted.log();
  const std::string restarted_log = restarted.log_with({"\"event\":\"clip_uploaded\""});
  EXPECT_NE(restarted_log.find("\"event\":\"clip_uploaded\""), std::string::npos) << restarted_log;
}

}  // namespace
}  // namespace sweepd::test::stream_poses_test
