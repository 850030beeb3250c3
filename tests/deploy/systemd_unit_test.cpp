// deploy/sweepd.service, checked by systemd's own tools and then run as its ExecStart runs:
// - `systemd-analyze verify` finds nothing to say (unknown keys, bad values, a missing
//   binary: ExecStart pointed at the built sweepd);
// - `systemd-analyze security --offline` rates its hardening at an exposure of 2.0 or less
//   (systemd's "OK" band; 1.4 when written);
// - the ExecStart line, with systemd's ${STATE_DIRECTORY} and ${CREDENTIALS_DIRECTORY}
//   substituted by test directories and /etc/sweepd/sweepd.conf by deploy/sweepd.conf, run
//   under a fake NOTIFY_SOCKET with the unit's WatchdogSec: READY=1 comes once it accepts, the
//   credential's token is required, the store is written to the state directory, and SIGTERM
//   gives STOPPING=1 and exit 0. (Ports are overridden by flags after the unit's: 7878 and
//   9464 may be taken here.)
// Each systemd-analyze part skips, saying so, where systemd-analyze is absent.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>

#include "tests/deploy/shell_command.h"
#include "tests/server/daemon_process.h"
#include "tests/server/http_probe.h"
#include "tests/server/notify_socket.h"

namespace sweepd::test::systemd_unit_test {
namespace {

using namespace std::chrono_literals;

const fs::path kSource = SWEEPD_SOURCE_DIR;
const fs::path kUnit = kSource / "deploy" / "sweepd.service";

// The value of `key=` in the unit (the last one, as systemd reads single-valued keys).
std::string unit_value(const std::string& key) {
  std::ifstream in(kUnit);
  std::string value;
  for (std::string line; std::getline(in, line);) {
    if (line.starts_with(key + "=")) value = line.substr(key.size() + 1);
  }
  return value;
}

// The unit with ExecStart's binary replaced by the built sweepd, in `directory`.
fs::path unit_with_built_binary(const fs::path& directory) {
  std::ifstream in(kUnit);
  std::stringstream text;
  text << in.rdbuf();
  const std::string unit =
      std::regex_replace(text.str(), std::regex("/usr/local/bin/sweepd"), SWEEPD_DAEMON);
  const fs::path file = directory / "sweepd.service";
  std::ofstream(file) << unit;
  return file;
}

class SystemdUnitTest : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = fresh_directory(::testing::UnitTest::GetInstance()->current_test_info()->name());
  }
  void TearDown() override { fs::remove_all(directory_); }
  fs::path directory_;
};

TEST_F(SystemdUnitTest, SystemdAnalyzeVerifyHasNothingToSay) {
  if (!have_program("systemd-analyze")) GTEST_SKIP() << "systemd-analyze is not installed";
  const fs::path unit = unit_with_built_binary(directory_);
  const CommandResult run = run_command("systemd-analyze verify '" + unit.string() + "'");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(run.output, "");
}

TEST_F(SystemdUnitTest, HardeningRatesOkWithSystemdAnalyzeSecurity) {
  if (!have_program("systemd-analyze")) GTEST_SKIP() << "systemd-analyze is not installed";
  const fs::path unit = unit_with_built_binary(directory_);
  // --threshold is on systemd's 0-100 scale: 20 is an exposure of 2.0.
  const CommandResult run =
      run_command("systemd-analyze security --offline=true --threshold=20 '" + unit.string() + "'");
  std::smatch level;
  ASSERT_TRUE(std::regex_search(run.output, level,
                                std::regex("Overall exposure level for sweepd.service: ([0-9.]+)")))
      << run.output;
  std::printf("systemd-analyze security: exposure %s\n", level[1].str().c_str());
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_LE(std::stod(level[1]), 2.0);
}

TEST_F(SystemdUnitTest, TheUnitsCommandLineServesAsSystemdWouldStartIt) {
  // ExecStart=/usr/local/bin/sweepd ARGS, with systemd's variables and the config path ours.
  std::string exec_start = unit_value("ExecStart");
  ASSERT_TRUE(exec_start.starts_with("/usr/local/bin/sweepd ")) << exec_start;
  const fs::path state = directory_ / "state";
  const fs::path credentials = directory_ / "credentials";
  fs::create_directories(state);
  fs::create_directories(credentials);
  std::ofstream(credentials / "token") << "unit-token\n";
  exec_start =
      std::regex_replace(exec_start, std::regex(R"(\$\{STATE_DIRECTORY\})"), state.string());
  exec_start = std::regex_replace(exec_start, std::regex(R"(\$\{CREDENTIALS_DIRECTORY\})"),
                                  credentials.string());
  exec_start = std::regex_replace(exec_start, std::regex("/etc/sweepd/sweepd.conf"),
                                  (kSource / "deploy" / "sweepd.conf").string());
  std::istringstream words(exec_start.substr(exec_start.find(' ') + 1));
  std::vector<std::string> args;
  for (std::string word; words >> word;) args.push_back(word);
  for (const char* flag : {"--port", "0", "--http-listen", "127.0.0.1:0", "--http-port-file"}) {
    args.push_back(flag);
  }
  args.push_back((directory_ / "http_port").string());

  // What systemd gives a Type=notify unit with WatchdogSec=.
  NotifySocket notify(directory_ / "notify");
  ASSERT_TRUE(notify.bound());
  const int watchdog_seconds = std::stoi(unit_value("WatchdogSec"));
  const std::string watchdog_usec = std::to_string(watchdog_seconds * 1'000'000LL);
  NotifyEnvironment environment(notify.path(), watchdog_usec.c_str());
  DaemonProcess daemon(directory_, args);
  ASSERT_TRUE(daemon.running()) << daemon.log();

  bool ready = false;
  while (const auto message = notify.receive(60s)) {
    if (message->text.starts_with("READY=1")) {
      ready = true;
      break;
    }
  }
  ASSERT_TRUE(ready) << daemon.log();
  const std::string log = daemon.log();
  EXPECT_NE(log.find("\"watchdog_ms\":" + std::to_string(watchdog_seconds * 1000)),
            std::string::npos)
      << log;
  EXPECT_NE(log.find("\"auth\":\"token\""), std::string::npos) << log;
  {
    FrameClient wrong(daemon.port());
    flatbuffers::FlatBufferBuilder builder;
    wrong.send_bytes(protocol::build_hello(builder, "wrong", "systemd_unit_test",
                                           protocol::PoseDelivery::InOrder, 1));
    const protocol::Message* refused = wrong.receive();
    ASSERT_NE(refused, nullptr);
    EXPECT_EQ(refused->body_type(), protocol::Body::Error);
    FrameClient right(daemon.port());
    EXPECT_NE(right.hello("unit-token"), nullptr);
  }
  bool stored = false;  // the default model's binding, named by its content id
  for (const fs::directory_entry& entry : fs::directory_iterator(state))
    stored = stored || entry.path().extension() == ".sweepbind";
  EXPECT_TRUE(stored) << "the store is not in the state directory";

  daemon.signal(SIGTERM);
  std::string stopping;
  while (const auto message = notify.receive(30s)) {
    if (message->text.starts_with("STOPPING=1")) {
      stopping = message->text;
      break;
    }
  }
  EXPECT_FALSE(stopping.empty()) << daemon.log();
  EXPECT_EQ(daemon.wait(), 0) << daemon.log();
}

}  // namespace
}  // namespace sweepd::test::systemd_unit_test
