// sweepd under systemd's notify protocol, seen as systemd sees it: the test binds a fake
// NOTIFY_SOCKET (tests/server/notify_socket.h), starts the real daemon with NOTIFY_SOCKET and
// WATCHDOG_USEC set, and reads what it sends: a STATUS= line per start-up stage, READY=1 only
// once the listeners accept (at that moment /readyz answers 200 and a client is welcomed),
// WATCHDOG=1 every half of WATCHDOG_USEC, STOPPING=1 on SIGTERM before it exits 0. Without
// NOTIFY_SOCKET, or with one nobody listens on, the daemon serves and stops as before.
#include <gtest/gtest.h>

#include <cstdlib>

#include "tests/server/daemon_process.h"
#include "tests/server/http_probe.h"
#include "tests/server/notify_socket.h"

namespace sweepd::test {
namespace {

using namespace std::chrono_literals;

// WATCHDOG_USEC the tests give: 1 s, so pings every 0.5 s.
constexpr auto kWatchdog = 1000ms;

class DaemonSystemdNotifyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = fresh_directory(::testing::UnitTest::GetInstance()->current_test_info()->name());
  }
  void TearDown() override {
    daemon_.reset();
    fs::remove_all(directory_);
  }

  // Starts the daemon on another thread (DaemonProcess waits for its port file), so that the
  // test reads the notify socket while the daemon starts. The environment is inherited.
  std::thread start_daemon() {
    return std::thread([this]() {
      daemon_ = std::make_unique<DaemonProcess>(
          directory_, std::vector<std::string>{"--http-listen", "127.0.0.1:0", "--http-port-file",
                                               (directory_ / "http_port").string()});
    });
  }

  fs::path directory_;
  std::unique_ptr<DaemonProcess> daemon_;
};

TEST_F(DaemonSystemdNotifyTest, ReadyOnlyOnceAcceptingThenWatchdogPingsThenStoppingOnSigterm) {
  if (!have_program("curl")) GTEST_SKIP() << "curl is not installed (deploy/install-deps.sh)";
  NotifySocket notify(directory_ / "notify");
  ASSERT_TRUE(notify.bound());
  const std::string watchdog_usec = std::to_string(kWatchdog.count() * 1000);
  NotifyEnvironment environment(notify.path(), watchdog_usec.c_str());
  std::thread starter = start_daemon();

  // The start-up stages in order, then READY=1; nothing else (no ping before READY).
  std::vector<std::string> before_ready;
  std::optional<NotifyMessage> ready;
  while (const auto message = notify.receive(60s)) {
    if (message->text.starts_with("READY=1")) {
      ready = message;
      break;
    }
    before_ready.push_back(message->text);
  }
  ASSERT_TRUE(ready.has_value()) << "no READY=1 within 60 s";
  // At the moment READY=1 is read, the side port already says ready and the protocol port
  // welcomes a client (both port files are written before the I/O thread runs).
  const int http_port = std::stoi(read_text(directory_ / "http_port"));
  const HttpReply readyz = curl_get(http_port, "/readyz");
  {
    FrameClient client(std::stoi(read_text(directory_ / "port")));
    EXPECT_TRUE(client.connected());
    EXPECT_NE(client.hello(""), nullptr);
  }
  starter.join();
  ASSERT_TRUE(daemon_ && daemon_->running());
  EXPECT_EQ(readyz.status, 200) << readyz.body;
  EXPECT_EQ(ready->text, "READY=1\nSTATUS=accepting");
  EXPECT_EQ(before_ready, (std::vector<std::string>{"STATUS=restoring the model store",
                                                    "STATUS=binding the default model",
                                                    "STATUS=opening the listeners"}));

  // WATCHDOG=1 every 0.5 s: over 2.6 s at least 4, and never a gap systemd would kill for
  // (WATCHDOG_USEC; the period leaves a scheduler delay of up to 0.5 s on this shared machine).
  std::vector<std::chrono::steady_clock::time_point> pings;
  const auto until = std::chrono::steady_clock::now() + 2600ms;
  while (std::chrono::steady_clock::now() < until) {
    const auto message = notify.receive(100ms);
    if (!message) continue;
    EXPECT_EQ(message->text, "WATCHDOG=1");
    pings.push_back(message->received);
  }
  EXPECT_GE(pings.size(), 4u);
  for (std::size_t i = 1; i < pings.size(); ++i) {
    EXPECT_LT(pings[i] - pings[i - 1], kWatchdog) << "ping " << i;
    EXPECT_GT(pings[i] - pings[i - 1], 250ms) << "ping " << i << " (pings come in a burst)";
  }

  daemon_->signal(SIGTERM);
  std::optional<NotifyMessage> stopping;
  while (const auto message = notify.receive(30s)) {
    if (message->text == "WATCHDOG=1") continue;
    stopping = message;
    break;
  }
  ASSERT_TRUE(stopping.has_value()) << daemon_->log();
  EXPECT_EQ(stopping->text, "STOPPING=1\nSTATUS=draining (shutting down)");
  EXPECT_EQ(daemon_->wait(), 0) << daemon_->log();
  EXPECT_EQ(daemon_->log().find("watchdog_probe_missed"), std::string::npos) << daemon_->log();
}

TEST_F(DaemonSystemdNotifyTest, WithoutNotifySocketTheDaemonServesAndStopsAsBefore) {
  unsetenv("NOTIFY_SOCKET");
  setenv("WATCHDOG_USEC", "1000000", 1);  // ignored without NOTIFY_SOCKET
  start_daemon().join();
  unsetenv("WATCHDOG_USEC");
  ASSERT_TRUE(daemon_ && daemon_->running());
  FrameClient client(daemon_->port());
  EXPECT_NE(client.hello(""), nullptr);
  daemon_->signal(SIGTERM);
  EXPECT_EQ(daemon_->wait(), 0) << daemon_->log();
  const std::string log = daemon_->log();
  EXPECT_NE(log.find("\"systemd_notify\":false"), std::string::npos) << log;
  EXPECT_NE(log.find("\"watchdog_ms\":0"), std::string::npos) << log;
  EXPECT_EQ(log.find("sd_notify_failed"), std::string::npos) << log;
}

TEST_F(DaemonSystemdNotifyTest, ANotifySocketNobodyListensOnIsLoggedOnceAndServingGoesOn) {
  NotifyEnvironment environment(directory_ / "nobody", "200000");
  start_daemon().join();
  ASSERT_TRUE(daemon_ && daemon_->running());
  FrameClient client(daemon_->port());
  EXPECT_NE(client.hello(""), nullptr);
  std::this_thread::sleep_for(300ms);  // a watchdog ping or two fail too
  daemon_->signal(SIGTERM);
  EXPECT_EQ(daemon_->wait(), 0) << daemon_->log();
  const std::string log = daemon_->log();
  const std::size_t first = log.find("sd_notify_failed");
  EXPECT_NE(first, std::string::npos) << log;
  EXPECT_EQ(log.find("sd_notify_failed", first + 1), std::string::npos) << log;
}

}  // namespace
}  // namespace sweepd::test
