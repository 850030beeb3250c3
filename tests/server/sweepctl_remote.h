// What the `sweepctl --server` tests share: the real sweepctl binary (SWEEPD_SWEEPCTL) run as
// a child process, one daemon per test suite (tests/server/daemon_process.h) with a token, and
// the shared male and CMU clip they pose.
#pragma once

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "tests/server/client_run.h"
#include "tests/server/daemon_process.h"
#include "tests/test_paths.h"

namespace sweepd::test {

// The real sweepctl with `arguments`: its exit code and stdout + stderr.
inline ClientRun run_sweepctl(const std::string& arguments) {
  return run_client(std::string(SWEEPD_SWEEPCTL) + " " + arguments);
}

inline std::vector<char> file_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

inline const fs::path kSharedMale = fs::path(SWEEPD_SHARED_DATA) / "models/makehuman_male_cmu.glb";
inline const fs::path kClip = fs::path(SWEEPD_SHARED_DATA) / "motion/cmu_01_01.bvh";
inline constexpr int kClipFrame = 300;  // arms and legs well away from the rest pose
inline constexpr const char* kRemoteTestToken = "remote-test-token";

// One daemon (with kRemoteTestToken) for a suite's tests; `server()` is the sweepctl flags reaching
// it.
class SweepctlRemote : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    directory_ = new fs::path(fresh_directory("sweepctl_remote"));
    daemon_ = new DaemonProcess(*directory_, {"--token", kRemoteTestToken});
  }
  static void TearDownTestSuite() {
    delete daemon_;
    fs::remove_all(*directory_);
    delete directory_;
  }
  void SetUp() override { ASSERT_TRUE(daemon_->running()) << daemon_->log(); }

  static std::string server() {
    return "--server 127.0.0.1:" + std::to_string(daemon_->port()) + " --token " + kRemoteTestToken;
  }
  static int port() { return daemon_->port(); }
  static std::uint32_t mannequin_id() { return daemon_->model_id(); }
  // A file in the suite's directory (the daemon's store is "store/").
  static fs::path path(const std::string& name) { return *directory_ / name; }
  static std::string log() { return daemon_->log(); }

 private:
  static inline fs::path* directory_ = nullptr;
  static inline DaemonProcess* daemon_ = nullptr;
};

}  // namespace sweepd::test
