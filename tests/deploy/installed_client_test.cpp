// The C++ client as another project uses it: `cmake --install --component client` into a
// fresh prefix, then client_examples/installed_client — a project of its own that knows
// sweepd only through find_package(sweepd_client) — is configured, built with this build's
// compiler and flags (a sanitized build's library needs its runtime), and run against a
// real daemon. Its rest pose must equal the in-tree client's for the same request.
#include <gtest/gtest.h>

#include <limits>
#include <regex>

#include "client/connection.h"
#include "tests/deploy/shell_command.h"
#include "tests/server/daemon_process.h"

namespace sweepd::test {
namespace {

std::string quoted(const std::string& text) { return "'" + text + "'"; }

// The extent along y of the daemon's rest pose of `model`, through the in-tree client.
float rest_height(int port, const std::string& model) {
  client::Connection connection("127.0.0.1:" + std::to_string(port));
  connection.hello("t0k", "installed_client_test");
  const protocol::ModelInfo& info = connection.load_model(model);
  const std::uint32_t model_id = info.model_id();
  const std::vector<protocol::Quat> rest(info.joint_names()->size(), protocol::Quat(0, 0, 0, 1));
  protocol::PoseFields pose;
  pose.model_id = model_id;
  pose.rotations = rest;
  connection.builder().Clear();
  connection.send(protocol::finish_message(connection.builder(),
                                           protocol::add_pose(connection.builder(), pose)));
  const protocol::PosedVertices& reply = connection.expect<protocol::PosedVertices>();
  std::vector<float> positions(3 * std::size_t{reply.vertex_count()});
  EXPECT_TRUE(protocol::copy_positions(reply, positions));
  float low = std::numeric_limits<float>::max(), high = std::numeric_limits<float>::lowest();
  for (std::size_t i = 1; i < positions.size(); i += 3) {
    low = std::min(low, positions[i]);
    high = std::max(high, positions[i]);
  }
  connection.close();
  return high - low;
}

TEST(InstalledClient, AnotherProjectBuildsAgainstTheInstalledPackageAndPoses) {
  const ScratchDirectory directory("installed_client");
  const fs::path prefix = directory / "prefix";
  const CommandResult install = run_command("cmake --install " + quoted(SWEEPD_BUILD_DIR) +
                                            " --component client --prefix " + quoted(prefix));
  ASSERT_EQ(install.exit_code, 0) << install.output;
  // The package is the client and the protocol, nothing of the server or the library.
  EXPECT_TRUE(fs::exists(prefix / "include/sweepd/client/connection.h"));
  EXPECT_TRUE(fs::exists(prefix / "include/sweepd/protocol/sweepd_generated.h"));
  EXPECT_FALSE(fs::exists(prefix / "include/sweepd/deform"));
  EXPECT_FALSE(fs::exists(prefix / "bin"));

  const fs::path build = directory / "build";
  const CommandResult configure = run_command(
      "cmake -S " + quoted(std::string(SWEEPD_SOURCE_DIR) + "/client_examples/installed_client") +
      " -B " + quoted(build) + " -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=" + quoted(prefix) +
      " -DCMAKE_CXX_COMPILER=" + quoted(SWEEPD_CXX_COMPILER) +
      " -DCMAKE_CXX_FLAGS=" + quoted(SWEEPD_CXX_FLAGS));
  ASSERT_EQ(configure.exit_code, 0) << configure.output;
  const CommandResult compile = run_command("cmake --build " + quoted(build));
  ASSERT_EQ(compile.exit_code, 0) << compile.output;

  DaemonProcess daemon(directory, {"--token", "t0k", "--mannequin-vertices", "2000"});
  ASSERT_TRUE(daemon.running()) << daemon.log();
  const CommandResult run = run_command("SWEEPD_TOKEN=t0k " + quoted(build / "rest_pose") +
                                        " 127.0.0.1:" + std::to_string(daemon.port()));
  ASSERT_EQ(run.exit_code, 0) << run.output << daemon.log();
  EXPECT_NE(run.output.find("model mannequin vertices"), std::string::npos) << run.output;

  std::smatch posed;
  ASSERT_TRUE(std::regex_search(run.output, posed,
                                std::regex(R"(posed mannequin vertices (\d+) height ([0-9.]+))")))
      << run.output;
  // The same request through the in-tree client: the same mesh, so the same extent to the
  // six decimals the example prints (rounding of one float: tolerance half a unit of 1e-6).
  const float height = rest_height(daemon.port(), "mannequin");
  EXPECT_GT(std::stoi(posed[1]), 1000);
  EXPECT_NEAR(std::stod(posed[2]), height, 0.5e-6 + 1e-9);
  EXPECT_GT(height, 1.0f);  // a standing adult mannequin, not an empty or collapsed mesh
}

}  // namespace
}  // namespace sweepd::test
