// The Blender add-on (client_examples/blender, zipped by the build) as a user runs it: Debian's
// Blender 3.4, headless, installs the zip from a fresh user folder, enables it, imports a body
// with an animation (`sweepctl rom`'s), and "Deform with sweepd" against a daemon on loopback
// puts a PC2-cached copy beside the mesh (and a DQS copy) — after a run with a wrong token ended
// with Blender's error report naming it and left nothing behind; the cached vertices are `sweepctl
// pose`'s frames of the file the add-on uploaded (tests/server/blender_addon.py does the Blender
// side and names its matching rule). The shared male over plain TCP, and a corpus body on another
// rig over TLS (the add-on trusting the test's CA). Skips where blender is absent.
#include <gtest/gtest.h>

#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "tests/deploy/shell_command.h"
#include "tests/scratch_directory.h"
#include "tests/server/client_run.h"
#include "tests/server/daemon_process.h"
#include "tests/server/sweepctl_remote.h"
#include "tests/server/test_certificates.h"

namespace sweepd::test::blender_addon_test {
namespace {

constexpr int kFirst = 14, kLast = 16;  // around the first move's peak: the body is bent

// A body, and whether the daemon speaks TLS (the add-on then trusts the test's CA).
struct AddonRun {
  const char* model;
  bool tls;
};

class BlenderAddon : public ::testing::TestWithParam<AddonRun> {};

// 1e-5 m: the daemon and sweepctl deform the same file with the same library; the cache goes
// through float64 axis and object-space turns and back to float32 in Blender's modifier.
TEST_P(BlenderAddon, CachedCopyHoldsSweepctlPoseFramesOfTheUploadedFile) {
  const fs::path model = fs::path(SWEEPD_SHARED_DATA) / "models" / GetParam().model;
  const fs::path addon = fs::path(SWEEPD_BUILD_DIR) / "client_examples/blender/sweepd_blender.zip";
  if (!fs::exists(model)) GTEST_SKIP() << "shared data absent: " << model;
  if (run_command("command -v blender").exit_code != 0)
    GTEST_SKIP() << "blender is not installed (Debian's package `blender`: "
                    "deploy/install-deps.sh installs it)";
  ASSERT_TRUE(fs::exists(addon)) << addon << ": the build's blender_addon target makes it";
  const ScratchDirectory scratch("blender_addon");  // removed after the daemon has stopped
  const fs::path& dir = scratch.path();
  std::vector<std::string> daemon_flags = {"--token", "t0k"};
  std::string tls_ca;
  if (GetParam().tls) {
    const std::optional<TestCertificates> certificates = TestCertificates::make(dir);
    if (!certificates) GTEST_SKIP() << "openssl is not installed: no certificates for TLS";
    daemon_flags.insert(daemon_flags.end(), {"--tls-cert", certificates->server_cert.string(),
                                             "--tls-key", certificates->server_key.string()});
    tls_ca = " " + certificates->ca.string();
  }
  DaemonProcess daemon(dir, daemon_flags);
  ASSERT_TRUE(daemon.running()) << daemon.log();
  const fs::path animated = dir / "animated.glb";
  const ClientRun rom = run_sweepctl("rom " + model.string() + " -o " + animated.string());
  ASSERT_EQ(rom.exit_code, 0) << rom.output;

  // BLENDER_USER_SCRIPTS: the zip installs into the test's folder, not the user's.
  const ClientRun blender =
      run_client("BLENDER_USER_SCRIPTS=" + (dir / "scripts").string() +
                 " blender -b --factory-startup --python-exit-code 1 --python " +
                 (fs::path(SWEEPD_SOURCE_DIR) / "tests/server/blender_addon.py").string() + " -- " +
                 addon.string() + " 127.0.0.1 " + std::to_string(daemon.port()) + " t0k " +
                 animated.string() + " " + (dir / "out").string() + " " + std::to_string(kFirst) +
                 " " + std::to_string(kLast) + " " + SWEEPD_SWEEPCTL + tls_ca);
  ASSERT_EQ(blender.exit_code, 0) << blender.output << daemon.log();
  EXPECT_NE(blender.output.find("animated.glb copies ok"), std::string::npos) << blender.output;
  EXPECT_NE(blender.output.find(
                "animated.glb refused: Error: sweepd: AuthFailed: the auth token is wrong"),
            std::string::npos)
      << "a wrong token ends the operator with Blender's error report naming it\n"
      << blender.output;
  std::istringstream lines(blender.output);
  int gaps = 0;
  double moved = 0.0;
  for (std::string line; std::getline(lines, line);) {
    if (!line.starts_with("animated.glb ")) continue;
    if (const std::size_t at = line.find(" moved "); at != std::string::npos) {
      moved = std::stod(line.substr(at + 7));
    } else if (const std::size_t at = line.find(" gap "); at != std::string::npos) {
      ++gaps;
      EXPECT_LE(std::stod(line.substr(at + 5)), 1e-5) << line;
    } else if (const std::size_t m = line.find(" matched "); m != std::string::npos) {
      std::istringstream counts(line.substr(m + 9));
      int matched = 0, total = -1;
      std::string of;
      counts >> matched >> of >> total;
      EXPECT_EQ(matched, total) << "every Blender vertex has a glTF copy: " << line;
    }
  }
  EXPECT_EQ(gaps, kLast - kFirst + 1) << blender.output;
  EXPECT_GT(moved, 0.01) << "the frames compared differ by centimetres, so a cache of the "
                            "wrong frame would fail\n"
                         << blender.output;
}

INSTANTIATE_TEST_SUITE_P(Bodies, BlenderAddon,
                         ::testing::Values(AddonRun{"makehuman_male_cmu.glb", false},
                                           AddonRun{"corpus/makehuman_female_slim_openpose.glb",
                                                    true}),
                         [](const ::testing::TestParamInfo<AddonRun>& info) {
                           return info.index == 0 ? std::string("SharedMale")
                                                  : std::string("CorpusFemaleSlimOverTls");
                         });

}  // namespace
}  // namespace sweepd::test::blender_addon_test
