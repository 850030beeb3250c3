// Strangers cannot starve members (issue 49 item 1), on loopback, where every peer shares one
// address as peers behind one NAT do: silent peers holding every slot for connections that
// have not said Hello do not keep an honest client with the token out (the oldest is shed and
// /metrics counts it), and authenticated connections have their own limit; a burst of wrong
// tokens is slowed (past the free failures no token of the address is compared until its wait
// ends; the refusals and the compared failures are counted exactly on /metrics and logged once
// per burst); a stranger that never says Hello is closed after the Hello deadline; WebSocket
// and Unix-socket strangers are held and shed by the same rule.
#include <gtest/gtest.h>

#include <thread>

#include "tests/server/daemon_process.h"
#include "tests/server/hostile_input.h"
#include "tests/server/http_probe.h"
#include "tests/server/pose_frames.h"

namespace sweepd::test::daemon_strangers_test {
namespace {

constexpr std::uint32_t kMannequinJoints = 31;  // mannequin/mannequin.h
const std::string kToken = "t0k";

// A daemon with a token and the HTTP side port, whose /metrics the tests read.
class StrangersTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!have_program("curl")) GTEST_SKIP() << "curl is not installed (deploy/install-deps.sh)";
    directory_ = fresh_directory(::testing::UnitTest::GetInstance()->current_test_info()->name());
  }
  void start(const std::vector<std::string>& flags) {
    const fs::path http_port_file = directory_ / "http_port";
    daemon_ = std::make_unique<DaemonProcess>(
        directory_, with({"--position-maps", "0", "--token", kToken, "--http-listen", "127.0.0.1:0",
                          "--http-port-file", http_port_file.string()},
                         flags));
    ASSERT_TRUE(daemon_->running()) << daemon_->log();
    http_port_ = std::stoi(read_text(http_port_file));
  }
  void TearDown() override {
    daemon_.reset();
    if (!directory_.empty()) fs::remove_all(directory_);
  }

  double metric_now(const std::string& series) {
    return metric(curl_get(http_port_, "/metrics").body, series);
  }
  // Polls /metrics until `series` reads `value` (the I/O thread counts a connection a moment
  // after the client's connect returns), for at most 10 s; the last value read.
  double metric_once(const std::string& series, double value) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    double now = metric_now(series);
    while (now != value && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      now = metric_now(series);
    }
    return now;
  }

  void expect_pose_served(FrameClient& client, std::uint64_t sequence) {
    const std::vector<protocol::Quat> wire = to_wire(bent_rotations(kMannequinJoints));
    ASSERT_TRUE(send_pose(client, pose_fields(daemon_->model_id(), sequence, wire)));
    const protocol::PosedVertices* reply = client.receive_as<protocol::PosedVertices>();
    ASSERT_NE(reply, nullptr);
    EXPECT_EQ(reply->sequence(), sequence);
  }

  fs::path directory_;
  std::unique_ptr<DaemonProcess> daemon_;
  int http_port_ = 0;
};

TEST_F(StrangersTest, SilentPeersHoldingEveryStrangerSlotDoNotKeepAnHonestClientOut) {
  constexpr int kStrangers = 8;
  // A Hello deadline far past the test: the silent peers hold their slots throughout.
  start({"--max-strangers", std::to_string(kStrangers), "--max-strangers-per-address",
         std::to_string(kStrangers), "--max-connections", "2", "--hello-timeout-ms", "60000"});
  std::vector<std::unique_ptr<FrameClient>> silent;
  for (int i = 0; i < kStrangers; ++i) {
    silent.push_back(std::make_unique<FrameClient>(daemon_->port()));
    ASSERT_TRUE(silent.back()->connected());
  }
  ASSERT_EQ(metric_once("sweepd_strangers_open", kStrangers), kStrangers);

  // The honest client takes the oldest silent peer's slot, says Hello and is served.
  FrameClient honest(daemon_->port());
  ASSERT_NE(honest.hello(kToken), nullptr);
  expect_pose_served(honest, 1);
  EXPECT_EQ(last_error_before_close(*silent.front()), protocol::ErrorCode::ConnectionLimit);
  EXPECT_EQ(metric_now("sweepd_strangers_shed_total"), 1.0);
  EXPECT_EQ(metric_once("sweepd_strangers_open", kStrangers - 1), kStrangers - 1);
  EXPECT_EQ(log_lines(daemon_->log(), "connection_cut",
                      "127.0.0.1 already holds 8 connections that have not said Hello"),
            1u);

  // Members have their own limit (2): a second honest client is admitted beside the strangers,
  // a third with the right token is refused for that limit, not for the strangers.
  FrameClient second(daemon_->port());
  ASSERT_NE(second.hello(kToken), nullptr);
  expect_pose_served(second, 2);
  FrameClient third(daemon_->port());
  flatbuffers::FlatBufferBuilder builder;
  ASSERT_TRUE(third.send_bytes(
      protocol::build_hello(builder, kToken, "third", protocol::PoseDelivery::InOrder, 1)));
  const protocol::Error* error = third.receive_as<protocol::Error>();
  ASSERT_NE(error, nullptr);
  EXPECT_EQ(error->code(), protocol::ErrorCode::ConnectionLimit);
  EXPECT_TRUE(error->fatal());
  EXPECT_EQ(error->message()->str(),
            "the server already holds its limit of 2 authenticated connections");
  expect_pose_served(honest, 3);
}

// The other doors: a WebSocket peer is a stranger of its TCP address like a TCP peer, every
// Unix-socket peer one of the address "unix". Four silent WebSocket peers (all 127.0.0.1 may
// hold) and two silent Unix-socket peers fill the six stranger slots; an honest Unix-socket
// client then sheds the oldest stranger of the address holding most (the first WebSocket peer,
// not a Unix one), and both honest clients, on the Unix socket and on WebSocket, are served.
TEST_F(StrangersTest, WebSocketAndUnixSocketStrangersAreShedByTheSameRule) {
  const ScratchDirectory sockets("strangers_unix");
  const fs::path unix_socket = sockets / "sweepd.sock";
  start(with(DaemonProcess::websocket_flags(directory_),
             {"--unix-socket", unix_socket.string(), "--max-strangers", "6",
              "--max-strangers-per-address", "4", "--hello-timeout-ms", "60000"}));
  std::vector<std::unique_ptr<FrameClient>> websocket, unix_peers;
  for (int i = 0; i < 4; ++i) {
    websocket.push_back(
        std::make_unique<FrameClient>(daemon_->websocket_port(), WebSocketUpgrade{}));
    ASSERT_EQ(websocket.back()->websocket_status(), 101);
  }
  for (int i = 0; i < 2; ++i) {
    unix_peers.push_back(std::make_unique<FrameClient>(unix_socket));
    ASSERT_TRUE(unix_peers.back()->connected());
  }
  ASSERT_EQ(metric_once("sweepd_strangers_open", 6), 6.0);

  FrameClient honest_unix(unix_socket);
  ASSERT_NE(honest_unix.hello(kToken), nullptr);
  expect_pose_served(honest_unix, 1);
  EXPECT_EQ(last_error_before_close(*websocket.front()), protocol::ErrorCode::ConnectionLimit);
  EXPECT_EQ(metric_now("sweepd_strangers_shed_total"), 1.0);
  EXPECT_EQ(log_lines(daemon_->log(), "connection_cut",
                      "the server already holds 6 connections that have not said Hello"),
            1u);

  FrameClient honest_websocket(daemon_->websocket_port(), WebSocketUpgrade{});
  ASSERT_NE(honest_websocket.hello(kToken), nullptr);
  expect_pose_served(honest_websocket, 2);
  EXPECT_EQ(metric_now("sweepd_strangers_shed_total"), 1.0);
  EXPECT_EQ(metric_once("sweepd_strangers_open", 5), 5.0);
}

// One Hello with `token` on a new connection: the fatal error's text, or "" for a Welcome.
std::string hello_answer(int port, const std::string& token) {
  FrameClient client(port);
  flatbuffers::FlatBufferBuilder builder;
  client.send_bytes(
      protocol::build_hello(builder, token, "guesser", protocol::PoseDelivery::InOrder, 1));
  const protocol::Message* message = client.receive();
  if (message == nullptr) return "no answer";
  if (message->body_as_Welcome() != nullptr) return "";
  const protocol::Error* error = message->body_as_Error();
  if (error == nullptr || error->code() != protocol::ErrorCode::AuthFailed) return "unexpected";
  return error->message()->str();
}

TEST_F(StrangersTest, AWrongTokenBurstIsSlowedCountedAndLoggedOnce) {
  constexpr int kFree = 3;
  constexpr int kWaitMs = 1500;  // first and longest wait: each compare past the free ones
  constexpr int kAttempts = 20;
  start({"--auth-free-failures", std::to_string(kFree), "--auth-backoff-ms",
         std::to_string(kWaitMs), "--auth-backoff-max-ms", std::to_string(kWaitMs)});
  const std::string wrong = "the auth token is wrong";
  const std::string unchecked = "too many wrong tokens from 127.0.0.1: no token from it is checked";
  int compared = 0, refused = 0;
  std::string last_refusal;
  const auto started = std::chrono::steady_clock::now();
  for (int a = 0; a < kAttempts; ++a) {
    const std::string answer = hello_answer(daemon_->port(), "guess" + std::to_string(a));
    if (answer == wrong) {
      ++compared;
    } else if (answer.starts_with(unchecked)) {
      ++refused;
      last_refusal = answer;
    } else {
      ADD_FAILURE() << "attempt " << a << ": " << answer;
    }
    // The free failures and the one that starts the first wait are all compared.
    if (a <= kFree) {
      EXPECT_EQ(answer, wrong) << "attempt " << a;
    }
  }
  const auto elapsed_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                              std::chrono::steady_clock::now() - started)
                              .count();
  // Slowed: past the first kFree + 1, each compare needs a whole wait to have passed, so
  // however slow the machine, no more were compared than the elapsed time allows (on a
  // quick one: 4 compared, 16 refused).
  EXPECT_GE(compared, kFree + 1);
  EXPECT_LE(compared, kFree + 1 + elapsed_ms / kWaitMs) << elapsed_ms << " ms";
  EXPECT_EQ(compared + refused, kAttempts);
  EXPECT_EQ(metric_now("sweepd_auth_failures_total"), compared);
  EXPECT_EQ(metric_now("sweepd_auth_backoff_refusals_total"), refused);
  EXPECT_EQ(metric_now("sweepd_errors_total{code=\"AuthFailed\"}"), kAttempts);

  // The refusal says how long to wait; after that the right token is let in.
  if (!last_refusal.empty()) {
    const int wait_ms = std::stoi(last_refusal.substr(unchecked.size() + 5));
    EXPECT_GT(wait_ms, 0);
    EXPECT_LE(wait_ms, kWaitMs);
    std::this_thread::sleep_for(std::chrono::milliseconds(wait_ms + 50));
  }
  EXPECT_EQ(hello_answer(daemon_->port(), kToken), "");

  // Logged once per burst: its first wrong token, and its counts once it has been quiet.
  const std::string log = daemon_->log_with({"\"event\":\"auth_failure_burst\""});
  EXPECT_EQ(log_lines(log, "auth_failed", ""), 1u) << log;
  EXPECT_EQ(log_lines(log, "auth_failure_burst",
                      "\"refused_unchecked\":" + std::to_string(refused) + ",\"seconds\""),
            1u)
      << log;
  EXPECT_EQ(
      log_lines(log, "auth_failure_burst", "\"wrong_tokens\":" + std::to_string(compared) + "}"),
      1u)
      << log;
}

TEST_F(StrangersTest, AStrangerThatNeverSaysHelloIsClosedAfterTheDeadline) {
  start({"--hello-timeout-ms", "300"});
  // Before connecting: the server's deadline starts at its accept, after this.
  const auto connected = std::chrono::steady_clock::now();
  FrameClient silent(daemon_->port());
  ASSERT_EQ(metric_once("sweepd_strangers_open", 1), 1.0);
  const protocol::Error* error = silent.receive_as<protocol::Error>();
  ASSERT_NE(error, nullptr);
  EXPECT_EQ(error->code(), protocol::ErrorCode::NotAuthenticated);
  EXPECT_TRUE(error->fatal());
  EXPECT_EQ(error->message()->str(), "no Hello within 300 ms");
  // Not before the deadline (a little slack for the clocks of two processes).
  EXPECT_GE(std::chrono::steady_clock::now() - connected, std::chrono::milliseconds(250));
  EXPECT_TRUE(silent.closed_by_server());
  EXPECT_EQ(metric_once("sweepd_strangers_open", 0), 0.0);
}

}  // namespace
}  // namespace sweepd::test::daemon_strangers_test
