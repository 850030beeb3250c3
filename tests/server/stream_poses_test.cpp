// client_examples/stream_poses against the real daemon: a CMU clip streamed InOrder is
// answered pose for pose; streamed LatestWins every pose is answered or counted as dropped.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <regex>

#include "tests/server/daemon_process.h"

namespace sweepd::test {
namespace {

struct ClientRun {
  int exit_code = -1;
  std::string output;
};

ClientRun run_stream_poses(const std::string& arguments) {
  const std::string command = std::string(SWEEPD_STREAM_POSES) + " " + arguments + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return {};
  ClientRun run;
  std::array<char, 4096> buffer;
  while (std::size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe)) {
    run.output.append(buffer.data(), n);
  }
  const int status = pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

// "poses: sent S, answered A, dropped D, errors E" from the client's report.
std::array<int, 4> pose_counts(const std::string& output) {
  std::smatch match;
  const std::regex line(R"(poses: sent (\d+), answered (\d+), dropped (\d+), errors (\d+))");
  if (!std::regex_search(output, match, line)) return {-1, -1, -1, -1};
  return {std::stoi(match[1]), std::stoi(match[2]), std::stoi(match[3]), std::stoi(match[4])};
}

class StreamPoses : public ::testing::Test {
 protected:
  void SetUp() override {
    clip_ = fs::path(SWEEPD_SHARED_DATA) / "motion" / "cmu_01_01.bvh";
    if (!fs::exists(clip_)) GTEST_SKIP() << "shared data absent: " << clip_;
    directory_ = fresh_directory("stream_poses");
    daemon_ =
        std::make_unique<DaemonProcess>(directory_, std::vector<std::string>{"--token", "t0k"});
    ASSERT_TRUE(daemon_->running()) << daemon_->log();
  }
  void TearDown() override {
    daemon_.reset();
    fs::remove_all(directory_);
  }
  std::string common_arguments() const {
    return "--port " + std::to_string(daemon_->port()) + " --token t0k --bvh " + clip_.string();
  }

  fs::path clip_, directory_;
  std::unique_ptr<DaemonProcess> daemon_;
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

}  // namespace
}  // namespace sweepd::test
