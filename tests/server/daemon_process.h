// DaemonProcess: the real sweepd binary (SWEEPD_DAEMON) run as a child process for the
// integration tests — on an ephemeral localhost port (--port 0 --port-file), with its own
// store directory, stderr (the JSON logs) captured to a file for failure messages.
// FrameClient: a blocking socket client speaking the sweepd framing, with a receive timeout,
// so a test fails instead of hanging when the server does not answer; on TCP, a Unix socket,
// or WebSocket (--ws-listen: one frame per binary message, the client side of sweepd's own
// WebSocketSession on websocketpp; wss over OpenSSL), so that every test helper taking a
// FrameClient works on all.
// ClipClientTest: a fixture for the client examples' tests — a daemon with token "t0k" in a
// fresh directory, and CMU clip 01_01 for the client to stream (skipped without shared data).
// The definitions are in daemon_process.cpp, compiled once (the library test_daemon_process)
// rather than in each of the 36 test files that include this header: under ASan they were
// half of each such file's compile time.
#pragma once

#include <gtest/gtest.h>
#include <openssl/types.h>
#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "protocol/framing.h"
#include "protocol/messages.h"
#include "server/transport/websocket_session.h"
#include "tests/scratch_directory.h"
#include "tests/test_paths.h"

namespace sweepd::test {

namespace fs = std::filesystem;

std::string read_text(const fs::path& file);
std::vector<std::uint8_t> read_bytes(const fs::path& file);

// A daemon's flags: `args` followed by `more`.
std::vector<std::string> with(std::vector<std::string> args, const std::vector<std::string>& more);

// The default model's size in a daemon whose test does not choose it (sweepd's own default is
// 20,000 vertices).
inline constexpr int kTestMannequinVertices = 2000;

class DaemonProcess {
 public:
  // `directory` holds the store (directory/store), the port file and the log. `wrapper`, when
  // given, is a command (absolute path first) that runs the daemon, e.g. strace -D ... --; it
  // must exec the daemon in this process for signal() and wait() to reach the daemon.
  DaemonProcess(const fs::path& directory, std::vector<std::string> extra_args,
                std::vector<std::string> wrapper = {});
  ~DaemonProcess();
  DaemonProcess(const DaemonProcess&) = delete;
  DaemonProcess& operator=(const DaemonProcess&) = delete;

  int port() const { return port_; }
  // The --ws-listen port of a daemon started with websocket_flags(directory).
  static std::vector<std::string> websocket_flags(const fs::path& directory);
  int websocket_port() const;
  pid_t pid() const { return pid_; }  // -1 once it has ended
  bool running() const { return pid_ > 0 && port_ > 0; }
  std::string log() const;
  // The log once it holds every one of `texts`, or as it is after 30 s. The daemon writes some
  // lines after the client has seen what they record (a TLS alert is sent before the handshake
  // failure is logged; a cut socket closes before its line is written).
  std::string log_with(std::initializer_list<std::string> texts) const;
  // The handle (protocol model_id) of the model called `name` the daemon holds since start-up
  // (the default "mannequin"), from its start-up log: handles come from content ids
  // (server/models/content_id.h), so a test cannot know them beforehand. 0 when not logged.
  std::uint32_t model_id(const std::string& name = "mannequin") const;

  void signal(int number);
  // Waits for the process to end; its exit code, or -signal when killed, or nullopt on timeout.
  std::optional<int> wait(std::chrono::seconds timeout = std::chrono::seconds(30));

 private:
  fs::path directory_, log_file_;
  pid_t pid_ = -1;
  int port_ = 0;
};

// The WebSocket upgrade a FrameClient asks for; origin "": none sent (not a browser).
struct WebSocketUpgrade {
  std::string origin;
  int receive_buffer_bytes = 0;  // > 0: SO_RCVBUF (a client that reads slowly)
  std::string tls_ca;            // wss: TLS first, trusting this CA (PEM); "": plain ws
};

class FrameClient {
 public:
  static constexpr int kTimeoutSeconds = 30;

  // A WebSocket client on the daemon's --ws-listen port: the upgrade, answered (or refused:
  // websocket_status() says with what) before the constructor returns.
  FrameClient(int port, const WebSocketUpgrade& upgrade);
  // receive_buffer_bytes > 0: SO_RCVBUF set before connecting (a client that reads slowly).
  explicit FrameClient(int port, int receive_buffer_bytes = 0);
  explicit FrameClient(const fs::path& unix_socket);
  ~FrameClient();
  FrameClient(const FrameClient&) = delete;
  FrameClient& operator=(const FrameClient&) = delete;

  bool connected() const { return connected_; }
  // The socket, for a test's own recvmsg (a descriptor passed with a reply).
  int fd() const { return fd_; }

  // On WebSocket: one binary message.
  bool send_bytes(std::span<const std::uint8_t> bytes);
  // WebSocket only: a text message (what a browser's send(string) makes).
  bool send_text(const std::string& text);
  bool send_raw(std::span<const std::uint8_t> bytes);

  // The next frame's Message, or nullptr at end of stream / timeout (valid until next call).
  const protocol::Message* receive();

  // The whole frame receive() last returned, length prefix included (valid until next call).
  std::span<const std::uint8_t> last_frame() const { return last_frame_; }

  // The next frame's body of type T, failing the test (and returning nullptr) otherwise.
  template <typename T>
  const T* receive_as() {
    const protocol::Message* message = receive();
    if (message == nullptr) {
      ADD_FAILURE() << "no reply (connection closed or timed out)";
      return nullptr;
    }
    const T* body = message->body_as<T>();
    if (body == nullptr)
      ADD_FAILURE() << "expected " << protocol::EnumNameBody(protocol::BodyTraits<T>::enum_value)
                    << ", got " << describe(*message);
    return body;
  }

  // True when the server has closed the connection (a read returns end of stream; on
  // WebSocket after its close frame, if any).
  bool closed_by_server();

  // Everything the server sends until it closes (an HTTP response to a request on the
  // WebSocket port), as text.
  std::string receive_text_until_closed();

  // WebSocket only: the session (its close code, text messages), and the upgrade's HTTP status.
  server::WebSocketSession& websocket() { return *websocket_; }
  int websocket_status() const { return websocket_ ? websocket_->http_status() : 0; }
  // wss: the TLS handshake failed (or was not tried).
  bool tls_failed() const { return tls_ == nullptr; }

  const protocol::Welcome* hello(const std::string& token,
                                 protocol::PoseDelivery delivery = protocol::PoseDelivery::InOrder);

 private:
  // A message's body type, and an Error's code and text, for a failure message.
  static std::string describe(const protocol::Message& message);
  void set_timeout();
  bool receive_exactly(std::uint8_t* out, std::size_t count);
  // WebSocket: what the session has for the server (its messages, pongs, close frames).
  bool flush_websocket();
  // WebSocket: one read from the socket into the session; false at its end or on timeout.
  bool read_websocket();
  // wss: a blocking TLS client on the socket (OpenSSL), checking the server's certificate.
  bool start_tls(const std::string& ca_file);

  struct TlsFree {
    void operator()(SSL_CTX* context) const;
    void operator()(SSL* tls) const;
  };

  int fd_ = -1;
  bool connected_ = false;
  std::unique_ptr<SSL_CTX, TlsFree> tls_context_;
  std::unique_ptr<SSL, TlsFree> tls_;
  std::unique_ptr<server::WebSocketSession> websocket_;
  std::size_t payload_taken_ = 0;
  bool socket_ended_ = false;
  std::vector<std::uint64_t> storage_;
  std::span<const std::uint8_t> last_frame_;
};

class ClipClientTest : public ::testing::Test {
 protected:
  // directory_name: under the temporary folder, one per test file.
  explicit ClipClientTest(std::string directory_name)
      : directory_name_(std::move(directory_name)) {}
  void SetUp() override;
  void TearDown() override;

  fs::path clip_, directory_;
  std::unique_ptr<DaemonProcess> daemon_;

 private:
  std::string directory_name_;
};

}  // namespace sweepd::test
