// sweepd's WebSocket listener (--ws-listen, issue 18 item 2): Hello, ListModels and Poses over
// WebSocket equal those over TCP bit for bit (and the round trips of both are printed); the
// TCP path's bad inputs, sent over WebSocket with the same helpers (tests/server/hostile_input.h),
// are refused as on TCP — plus the WebSocket-only ones: text messages, a message past the
// limit before Hello, a refused Origin, plain HTTP on the WebSocket port — while the daemon
// serves an honest WebSocket client throughout. With --tls-cert the listener serves wss.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <thread>

#include "tests/server/daemon_process.h"
#include "tests/server/hostile_input.h"
#include "tests/server/http_probe.h"
#include "tests/server/pose_frames.h"
#include "tests/server/test_certificates.h"

namespace sweepd::test::daemon_websocket_test {
namespace {

constexpr char kToken[] = "ws-t0k";
constexpr int kTimeoutMs = 1500;  // Hello, frame and send timeouts of the daemon under test
constexpr int kIdleTimeoutMs = 3000;
constexpr std::uint16_t kCloseNormal = 1000, kCloseUnsupportedData = 1003,
                        kCloseMessageTooBig = 1009;

double percentile(std::vector<double> values, double p) {
  std::sort(values.begin(), values.end());
  return values[static_cast<std::size_t>(p * static_cast<double>(values.size() - 1))];
}

class DaemonWebSocket : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    directory_ = new fs::path(fresh_directory("websocket"));
    daemon_ = new DaemonProcess(
        *directory_,
        with(DaemonProcess::websocket_flags(*directory_),
             // The default 20k model: replies large enough to fill a non-reader's socket.
             {"--mannequin-vertices", "20000", "--http-listen", "127.0.0.1:0", "--http-port-file",
              (*directory_ / "http_port").string(), "--token", kToken, "--position-maps", "0",
              "--hello-timeout-ms", std::to_string(kTimeoutMs), "--frame-timeout-ms",
              std::to_string(kTimeoutMs), "--send-timeout-ms", std::to_string(kTimeoutMs),
              "--idle-timeout-ms", std::to_string(kIdleTimeoutMs)}));
  }
  static void TearDownTestSuite() {
    delete daemon_;
    fs::remove_all(*directory_);
    delete directory_;
  }
  void SetUp() override { ASSERT_TRUE(daemon_->running()) << daemon_->log(); }

  static int ws_port() { return daemon_->websocket_port(); }
  static std::vector<protocol::Quat> wire(float phase = 0.0f) {
    return to_wire(bent_rotations(31, phase));  // the mannequin's joints (mannequin/mannequin.h)
  }
  // A WebSocket client that has said Hello with the right token.
  static std::unique_ptr<FrameClient> greeted() {
    auto client = std::make_unique<FrameClient>(ws_port(), WebSocketUpgrade{});
    EXPECT_EQ(client->websocket_status(), 101);
    EXPECT_NE(client->hello(kToken), nullptr);
    return client;
  }
  // The daemon still serves: a WebSocket Hello and a Pose.
  // The connection_cut lines that name `reason`, once there is one: the daemon may log a cut
  // after its client has seen the close.
  static std::size_t cuts_logged(const std::string& reason) {
    return log_lines(daemon_->log_with({reason}), "connection_cut", reason);
  }

  static void expect_still_serving() {
    std::unique_ptr<FrameClient> client = greeted();
    ASSERT_TRUE(send_pose(*client, pose_fields(daemon_->model_id(), 5, wire())));
    const protocol::PosedVertices* reply = client->receive_as<protocol::PosedVertices>();
    ASSERT_NE(reply, nullptr);
    EXPECT_EQ(reply->sequence(), 5u);
  }

  static fs::path* directory_;
  static DaemonProcess* daemon_;
};
fs::path* DaemonWebSocket::directory_ = nullptr;
DaemonProcess* DaemonWebSocket::daemon_ = nullptr;

TEST_F(DaemonWebSocket, HelloListModelsAndPosesEqualThoseOverTcpBitForBit) {
  std::unique_ptr<FrameClient> websocket = greeted();
  FrameClient tcp(daemon_->port());
  ASSERT_NE(tcp.hello(kToken), nullptr);
  {
    flatbuffers::FlatBufferBuilder builder;
    websocket->send_bytes(
        protocol::finish_message(builder, protocol::CreateListModels(builder), 9));
  }
  const protocol::ModelList* models = websocket->receive_as<protocol::ModelList>();
  ASSERT_NE(models, nullptr);
  ASSERT_GE(models->models()->size(), 1u);
  EXPECT_EQ(models->models()->Get(0)->name()->str(), "mannequin");
  for (std::uint64_t sequence = 1; sequence <= 3; ++sequence) {
    const std::vector<protocol::Quat> rotations = wire(0.7f * static_cast<float>(sequence));
    protocol::PoseFields fields = pose_fields(daemon_->model_id(), sequence, rotations);
    fields.normals = true;
    ASSERT_TRUE(send_pose(*websocket, fields));
    const protocol::PosedVertices* over_websocket =
        websocket->receive_as<protocol::PosedVertices>();
    ASSERT_NE(over_websocket, nullptr);
    const std::vector<float> ws_positions = copy_floats(over_websocket->positions_f32());
    const std::vector<float> ws_normals = copy_floats(over_websocket->normals_f32());
    ASSERT_TRUE(send_pose(tcp, fields));
    const protocol::PosedVertices* over_tcp = tcp.receive_as<protocol::PosedVertices>();
    ASSERT_NE(over_tcp, nullptr);
    const std::vector<float> tcp_positions = copy_floats(over_tcp->positions_f32());
    const std::vector<float> tcp_normals = copy_floats(over_tcp->normals_f32());
    ASSERT_GT(ws_positions.size(), 3000u);
    // Bit for bit: WebSocket carries the same frames.
    EXPECT_TRUE(same_bits(ws_positions, tcp_positions));
    EXPECT_TRUE(same_bits(ws_normals, tcp_normals));
  }

  // Round trips of the same pose, WebSocket and TCP taking turns (figures, not asserted: the
  // machine is shared).
  constexpr int kRoundTrips = 300;
  const std::vector<protocol::Quat> rotations = wire(0.3f);
  std::vector<double> ws_ms, tcp_ms;
  for (int i = 0; i < kRoundTrips; ++i) {
    for (FrameClient* client : {websocket.get(), &tcp}) {
      const auto start = std::chrono::steady_clock::now();
      ASSERT_TRUE(send_pose(*client, pose_fields(daemon_->model_id(), 100 + i, rotations)));
      ASSERT_NE(client->receive_as<protocol::PosedVertices>(), nullptr);
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count();
      (client == &tcp ? tcp_ms : ws_ms).push_back(ms);
    }
  }
  std::printf(
      "pose round trip, %d each, 20k-vertex mannequin, positions only: WebSocket p50 %.3f ms "
      "p99 %.3f ms; TCP p50 %.3f ms p99 %.3f ms\n",
      kRoundTrips, percentile(ws_ms, 0.5), percentile(ws_ms, 0.99), percentile(tcp_ms, 0.5),
      percentile(tcp_ms, 0.99));
  const std::string log = daemon_->log();
  EXPECT_GE(log_lines(log, "websocket_open", ""), 1u) << log;

  // /metrics counts WebSocket connections among all and on their own: these two are open.
  if (!have_program("curl")) GTEST_SKIP() << "curl is not installed (deploy/install-deps.sh)";
  const HttpReply metrics = curl_get(std::stoi(read_text(*directory_ / "http_port")), "/metrics");
  EXPECT_EQ(metric(metrics.body, "sweepd_connections_open"), 2.0) << metrics.body;
  EXPECT_EQ(metric(metrics.body, "sweepd_websocket_connections_open"), 1.0);
  EXPECT_GE(metric(metrics.body, "sweepd_websocket_connections_accepted_total"), 1.0);
}

TEST_F(DaemonWebSocket, AWrongTokenAndARequestBeforeHelloAreRefusedAsOnTcp) {
  FrameClient wrong(ws_port(), WebSocketUpgrade{});
  flatbuffers::FlatBufferBuilder builder;
  wrong.send_bytes(protocol::build_hello(builder, "not-the-token", "ws_test"));
  EXPECT_EQ(last_error_before_close(wrong), protocol::ErrorCode::AuthFailed);
  EXPECT_EQ(wrong.websocket().peer_close_code(), kCloseNormal);  // after the fatal Error

  FrameClient early(ws_port(), WebSocketUpgrade{});
  builder.Clear();
  early.send_bytes(protocol::finish_message(builder, protocol::CreateListModels(builder), 1));
  EXPECT_EQ(last_error_before_close(early), protocol::ErrorCode::NotAuthenticated);
  expect_still_serving();
}

TEST_F(DaemonWebSocket, MalformedFramesAreAnsweredAndSixteenCloseTheSession) {
  std::unique_ptr<FrameClient> garbage = greeted();
  const std::vector<std::uint8_t> junk = garbage_frame();
  for (int f = 0; f < 20; ++f) garbage->send_bytes(junk);
  EXPECT_EQ(last_error_before_close(*garbage), protocol::ErrorCode::BadFrame);
  EXPECT_GE(cuts_logged("16 bad frames"), 1u);
  expect_still_serving();
}

TEST_F(DaemonWebSocket, OversizedFramesAndMessagesBeforeHelloAreCut) {
  // A frame announcing 1 MiB in a small message: the frame reader's limit, as on TCP.
  FrameClient announced(ws_port(), WebSocketUpgrade{});
  announced.send_bytes(length_prefix(1u << 20));
  EXPECT_EQ(last_error_before_close(announced), protocol::ErrorCode::FrameTooLarge);
  // A message of 70 KiB: refused from its header (1009), before its payload is taken.
  FrameClient large(ws_port(), WebSocketUpgrade{});
  std::vector<std::uint8_t> message = length_prefix(70u << 10);
  message.resize(4 + (70u << 10), 0x11);
  large.send_bytes(message);
  EXPECT_TRUE(large.closed_by_server());
  EXPECT_EQ(large.websocket().peer_close_code(), kCloseMessageTooBig);
  const std::string log = daemon_->log_with(
      {"before Hello a frame may have at most 65536 bytes", "WebSocket closed with 1009"});
  EXPECT_GE(log_lines(log, "connection_cut", "before Hello a frame may have at most 65536 bytes"),
            1u);
  EXPECT_GE(log_lines(log, "connection_cut", "WebSocket closed with 1009"), 1u) << log;
  expect_still_serving();
}

TEST_F(DaemonWebSocket, ATextMessageEndsTheSessionWithUnsupportedData) {
  std::unique_ptr<FrameClient> client = greeted();
  ASSERT_TRUE(client->send_text("{\"type\": \"Pose\"}"));
  EXPECT_TRUE(client->closed_by_server());
  EXPECT_EQ(client->websocket().peer_close_code(), kCloseUnsupportedData);
  EXPECT_GE(cuts_logged("a text message"), 1u);
  expect_still_serving();
}

TEST_F(DaemonWebSocket, AnOriginOfAnotherSiteIsRefusedAndTheSameHostIsNot) {
  FrameClient other_site(
      ws_port(),
      WebSocketUpgrade{.origin = "https://evil.example", .receive_buffer_bytes = 0, .tls_ca = ""});
  EXPECT_EQ(other_site.websocket_status(), 403);
  EXPECT_TRUE(other_site.closed_by_server());
  EXPECT_GE(cuts_logged("Origin https://evil.example is not"), 1u);
  FrameClient same_host(
      ws_port(),
      WebSocketUpgrade{.origin = "http://127.0.0.1:8080", .receive_buffer_bytes = 0, .tls_ca = ""});
  EXPECT_EQ(same_host.websocket_status(), 101);
  EXPECT_NE(same_host.hello(kToken), nullptr);
  expect_still_serving();
}

TEST_F(DaemonWebSocket, PlainHttpOnTheWebSocketPortGets426) {
  FrameClient http(ws_port());
  const std::string request = "GET /metrics HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";
  http.send_raw({reinterpret_cast<const std::uint8_t*>(request.data()), request.size()});
  const std::string response = http.receive_text_until_closed();
  EXPECT_TRUE(response.starts_with("HTTP/1.1 426")) << response;
  // The TCP protocol's own Hello on the WebSocket port never ends an HTTP request: cut at the
  // handshake deadline, with no reply.
  FrameClient frames(ws_port());
  flatbuffers::FlatBufferBuilder builder;
  frames.send_raw(protocol::build_hello(builder, kToken, "tcp_client"));
  EXPECT_EQ(frames.receive_text_until_closed(), "");
  EXPECT_GE(cuts_logged("WebSocket handshake failed: HTTP 426"), 1u);
  expect_still_serving();
}

TEST_F(DaemonWebSocket, SilentTricklingIdleAndNonReadingClientsAreCutWhileOthersAreServed) {
  std::atomic<bool> done = false;
  std::atomic<int> answered = 0, failed = 0;
  std::thread honest([&] {
    std::unique_ptr<FrameClient> client = greeted();
    for (std::uint64_t p = 0; !done; ++p) {
      if (!send_pose(*client, pose_fields(daemon_->model_id(), p, wire())) ||
          client->receive_as<protocol::PosedVertices>() == nullptr) {
        ++failed;
        return;
      }
      ++answered;
    }
  });
  const auto opened = std::chrono::steady_clock::now();
  FrameClient no_upgrade(ws_port());  // TCP, never a byte of HTTP
  FrameClient no_hello(ws_port(), WebSocketUpgrade{});
  std::unique_ptr<FrameClient> trickler = greeted();
  ASSERT_TRUE(trickler->send_bytes(length_prefix(1u << 20)));  // a frame begun, never finished
  std::unique_ptr<FrameClient> idle = greeted();
  auto non_reader = std::make_unique<FrameClient>(
      ws_port(), WebSocketUpgrade{.origin = "", .receive_buffer_bytes = 4096, .tls_ca = ""});
  ASSERT_NE(non_reader->hello(kToken), nullptr);
  for (int p = 0; p < 40; ++p)
    ASSERT_TRUE(send_pose(*non_reader, pose_fields(daemon_->model_id(), p, wire())));

  EXPECT_TRUE(no_upgrade.closed_by_server());
  EXPECT_EQ(last_error_before_close(no_hello), protocol::ErrorCode::NotAuthenticated);
  EXPECT_EQ(last_error_before_close(*trickler), protocol::ErrorCode::BadFrame);
  const protocol::Error* idle_error = idle->receive_as<protocol::Error>();
  ASSERT_NE(idle_error, nullptr);
  EXPECT_NE(idle_error->message()->str().find("no request for 3000 ms"), std::string::npos);
  std::this_thread::sleep_for(std::chrono::milliseconds(2 * kTimeoutMs));
  done = true;
  honest.join();
  EXPECT_EQ(failed, 0);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - opened).count();
  EXPECT_GT(answered, 10) << "the honest client in " << seconds << " s";
  const std::string log =
      daemon_->log_with({"no WebSocket handshake within 1500 ms", "was not whole within 1500 ms",
                         "took no reply bytes for 1500 ms"});
  EXPECT_GE(log_lines(log, "connection_cut", "no WebSocket handshake within 1500 ms"), 1u) << log;
  EXPECT_GE(log_lines(log, "connection_cut", "was not whole within 1500 ms"), 1u);
  EXPECT_GE(log_lines(log, "connection_cut", "took no reply bytes for 1500 ms"), 1u);
  expect_still_serving();
}

TEST(DaemonWebSocketBudget, AMessagePastTheSharedBudgetIsRefusedAndTheSessionGoesOn) {
  const fs::path directory = fresh_directory("ws_budget");
  DaemonProcess daemon(
      directory, with(DaemonProcess::websocket_flags(directory),
                      {"--position-maps", "0", "--max-buffered-bytes", std::to_string(1 << 20)}));
  ASSERT_TRUE(daemon.running()) << daemon.log();
  FrameClient client(daemon.websocket_port(), WebSocketUpgrade{});
  ASSERT_NE(client.hello(""), nullptr);
  expect_frame_past_budget_refused(client, daemon.model_id());
  fs::remove_all(directory);
}

TEST(DaemonWebSocketTls, WssCarriesTheSameFramesAndAPlainClientIsCut) {
  const fs::path directory = fresh_directory("wss");
  const std::optional<TestCertificates> certificates = TestCertificates::make(directory);
  if (!certificates) GTEST_SKIP() << "openssl is not installed (deploy/install-deps.sh)";
  DaemonProcess daemon(directory, with(DaemonProcess::websocket_flags(directory),
                                       {"--token", kToken, "--position-maps", "0",
                                        "--mannequin-vertices", "2000", "--hello-timeout-ms", "400",
                                        "--tls-cert", certificates->server_cert.string(),
                                        "--tls-key", certificates->server_key.string(),
                                        "--unix-socket", (directory / "sweepd.sock").string()}));
  ASSERT_TRUE(daemon.running()) << daemon.log();
  const int ws_port = daemon.websocket_port();
  FrameClient secure(
      ws_port, WebSocketUpgrade{
                   .origin = "", .receive_buffer_bytes = 0, .tls_ca = certificates->ca.string()});
  ASSERT_FALSE(secure.tls_failed());
  ASSERT_EQ(secure.websocket_status(), 101);
  ASSERT_NE(secure.hello(kToken), nullptr);
  FrameClient unix_socket(directory / "sweepd.sock");
  ASSERT_NE(unix_socket.hello(kToken), nullptr);
  const std::vector<protocol::Quat> rotations = to_wire(bent_rotations(31));
  protocol::PoseFields fields = pose_fields(daemon.model_id(), 1, rotations);
  fields.normals = true;
  ASSERT_TRUE(send_pose(secure, fields));
  const protocol::PosedVertices* over_wss = secure.receive_as<protocol::PosedVertices>();
  ASSERT_NE(over_wss, nullptr);
  const std::vector<float> wss_positions = copy_floats(over_wss->positions_f32());
  ASSERT_TRUE(send_pose(unix_socket, fields));
  const protocol::PosedVertices* over_unix = unix_socket.receive_as<protocol::PosedVertices>();
  ASSERT_NE(over_unix, nullptr);
  const std::vector<float> unix_positions = copy_floats(over_unix->positions_f32());
  ASSERT_GT(wss_positions.size(), 3000u);
  // Bit for bit: wss carries the same frames.
  EXPECT_TRUE(same_bits(wss_positions, unix_positions));

  // A plain WebSocket client on the wss port: its HTTP request is no TLS handshake.
  FrameClient plain(ws_port, WebSocketUpgrade{});
  EXPECT_NE(plain.websocket_status(), 101);
  EXPECT_TRUE(plain.closed_by_server());
  const std::string log = daemon.log_with({"TLS handshake failed"});
  EXPECT_GE(log_lines(log, "connection_cut", "TLS handshake failed"), 1u) << log;
  EXPECT_GE(log_lines(log, "tls_established", "TLSv1.3"), 1u) << log;
  EXPECT_GE(log_lines(log, "websocket_open", ""), 1u) << log;
  fs::remove_all(directory);
}

}  // namespace
}  // namespace sweepd::test::daemon_websocket_test
