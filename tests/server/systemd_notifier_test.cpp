// SystemdNotifier and WatchdogPinger in this process, against a fake notify socket
// (tests/server/notify_socket.h): each readiness stage is one datagram (STATUS=, with READY=1
// at accepting and STOPPING=1 at draining); without NOTIFY_SOCKET nothing is sent and no
// watchdog is asked for; WATCHDOG_USEC is read only with NOTIFY_SOCKET, and WATCHDOG_PID of
// another process turns it off; the pinger sends WATCHDOG=1 every half timeout while its probe
// answers and none while it does not (a wedged I/O thread).
#include "server/systemd_notifier.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <thread>

#include "server/watchdog_pinger.h"
#include "tests/server/daemon_process.h"
#include "tests/server/notify_socket.h"

namespace sweepd::test {
namespace {

using namespace std::chrono_literals;
using server::Readiness;
using server::SystemdNotifier;

class SystemdNotifierTest : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = fresh_directory("systemd_notifier");
    socket_ = std::make_unique<NotifySocket>(directory_ / "notify");
    ASSERT_TRUE(socket_->bound());
  }
  void TearDown() override {
    socket_.reset();
    fs::remove_all(directory_);
  }
  std::string next(std::chrono::milliseconds timeout = 2000ms) {
    const auto message = socket_->receive(timeout);
    return message ? message->text : "(none)";
  }

  fs::path directory_;
  std::unique_ptr<NotifySocket> socket_;
};

TEST_F(SystemdNotifierTest, EachStageIsOneMessageWithReadyAtAcceptingAndStoppingAtDraining) {
  NotifyEnvironment environment(socket_->path());
  SystemdNotifier notifier;
  EXPECT_TRUE(notifier.enabled());
  EXPECT_FALSE(notifier.watchdog_timeout().has_value());
  Readiness readiness([&notifier](Readiness::Stage stage) { notifier.stage(stage); });
  readiness.set(Readiness::Stage::kBindingDefaultModel);
  readiness.set(Readiness::Stage::kOpeningListeners);
  readiness.set(Readiness::Stage::kAccepting);
  readiness.set(Readiness::Stage::kDraining);
  notifier.status("failed: example");
  EXPECT_EQ(next(), "STATUS=binding the default model");
  EXPECT_EQ(next(), "STATUS=opening the listeners");
  EXPECT_EQ(next(), "READY=1\nSTATUS=accepting");
  EXPECT_EQ(next(), "STOPPING=1\nSTATUS=draining (shutting down)");
  EXPECT_EQ(next(), "STATUS=failed: example");
  EXPECT_EQ(next(100ms), "(none)");
}

TEST_F(SystemdNotifierTest, WithoutNotifySocketNothingIsSentAndNoWatchdogIsAskedFor) {
  unsetenv("NOTIFY_SOCKET");
  setenv("WATCHDOG_USEC", "200000", 1);  // systemd never sets one without the other
  SystemdNotifier notifier;
  unsetenv("WATCHDOG_USEC");
  EXPECT_FALSE(notifier.enabled());
  EXPECT_FALSE(notifier.watchdog_timeout().has_value());
  notifier.stage(Readiness::Stage::kAccepting);
  notifier.watchdog_ping();
  EXPECT_EQ(next(100ms), "(none)");
}

TEST_F(SystemdNotifierTest, WatchdogTimeoutIsReadAndIgnoredWhenMeantForAnotherProcess) {
  {
    NotifyEnvironment environment(socket_->path(), "1500000");
    SystemdNotifier notifier;
    ASSERT_TRUE(notifier.watchdog_timeout().has_value());
    EXPECT_EQ(notifier.watchdog_timeout()->count(), 1'500'000);
  }
  {
    const std::string other_pid = std::to_string(getpid() + 1);
    NotifyEnvironment environment(socket_->path(), "1500000", other_pid.c_str());
    EXPECT_FALSE(SystemdNotifier().watchdog_timeout().has_value());
  }
}

TEST_F(SystemdNotifierTest, PingerPingsEveryHalfTimeoutOnlyWhileTheProbeAnswers) {
  NotifyEnvironment environment(socket_->path());
  SystemdNotifier notifier;
  std::atomic<bool> answering{false};
  std::atomic<int> probes{0};
  {
    // 400 ms timeout: a probe every 200 ms. First 500 ms unanswered (a wedged I/O thread).
    server::WatchdogPinger pinger(notifier, 400ms, [&](std::chrono::milliseconds wait) {
      ++probes;
      if (answering) return true;
      std::this_thread::sleep_for(wait);  // as a probe that times out
      return false;
    });
    EXPECT_EQ(next(500ms), "(none)") << "a ping while the probe did not answer";
    answering = true;
    const auto first = socket_->receive(2000ms);
    ASSERT_TRUE(first.has_value());
    EXPECT_EQ(first->text, "WATCHDOG=1");
    auto previous = first->received;
    for (int i = 0; i < 4; ++i) {
      const auto ping = socket_->receive(2000ms);
      ASSERT_TRUE(ping.has_value());
      EXPECT_EQ(ping->text, "WATCHDOG=1");
      // Every 200 ms; what systemd needs is a gap below the 400 ms timeout, and not a burst
      // (at least 100 ms: half a period of scheduler delay tolerated on this shared machine).
      const auto gap = ping->received - previous;
      EXPECT_GE(gap, 100ms);
      EXPECT_LT(gap, 400ms);
      previous = ping->received;
    }
  }
  EXPECT_GE(probes.load(), 6);
  EXPECT_EQ(next(400ms), "(none)") << "a ping after the pinger stopped";
}

}  // namespace
}  // namespace sweepd::test
