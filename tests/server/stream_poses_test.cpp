// client_examples/stream_poses against the real daemon: a CMU clip streamed InOrder is
// answered pose for pose; streamed LatestWins every pose is answered or counted as dropped; a
// glTF file's animation (--clip-from, --clip; protocol 1.7) streams like a BVH, and an unknown
// animation name ends the client naming the file's animations.
#include <gtest/gtest.h>

#include <array>

#include "io/gltf_load.h"
#include "tests/io/baked_gltf_clip.h"
#include "tests/server/client_run.h"
#include "tests/server/daemon_process.h"

namespace sweepd::test {
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

}  // namespace
}  // namespace sweepd::test
