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
#pragma once

#include <gtest/gtest.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <openssl/ssl.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "protocol/framing.h"
#include "protocol/messages.h"
#include "server/transport/websocket_session.h"
#include "tests/scratch_directory.h"

namespace sweepd::test {

namespace fs = std::filesystem;

inline std::string read_text(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

inline std::vector<std::uint8_t> read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A daemon's flags: `args` followed by `more`.
inline std::vector<std::string> with(std::vector<std::string> args,
                                     const std::vector<std::string>& more) {
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

class DaemonProcess {
 public:
  // `directory` holds the store (directory/store), the port file and the log. `wrapper`, when
  // given, is a command (absolute path first) that runs the daemon, e.g. strace -D ... --; it
  // must exec the daemon in this process for signal() and wait() to reach the daemon.
  DaemonProcess(const fs::path& directory, std::vector<std::string> extra_args,
                std::vector<std::string> wrapper = {})
      : directory_(directory) {
    const fs::path port_file = directory / "port";
    fs::remove(port_file);
    std::vector<std::string> args = {
        SWEEPD_DAEMON, "--port", "0", "--port-file", port_file, "--store-dir", directory / "store"};
    args.insert(args.end(), extra_args.begin(), extra_args.end());
    args.insert(args.begin(), wrapper.begin(), wrapper.end());
    log_file_ = directory / "sweepd.log";
    pid_ = fork();
    if (pid_ == 0) {
      const std::string log = log_file_.string();
      std::freopen(log.c_str(), "w", stderr);  // this run's log only
      std::freopen("/dev/null", "w", stdout);
      std::vector<char*> argv;
      for (std::string& arg : args) argv.push_back(arg.data());
      argv.push_back(nullptr);
      execv(argv[0], argv.data());
      _exit(127);
    }
    // The port file appears (written whole, then renamed) once the listener is bound.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (std::chrono::steady_clock::now() < deadline) {
      if (fs::exists(port_file)) {
        port_ = std::stoi(read_text(port_file));
        return;
      }
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    ADD_FAILURE() << "sweepd did not start; log:\n" << log();
  }
  ~DaemonProcess() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  DaemonProcess(const DaemonProcess&) = delete;
  DaemonProcess& operator=(const DaemonProcess&) = delete;

  int port() const { return port_; }
  // The --ws-listen port of a daemon started with websocket_flags(directory).
  static std::vector<std::string> websocket_flags(const fs::path& directory) {
    return {"--ws-listen", "127.0.0.1:0", "--ws-port-file", (directory / "ws_port").string()};
  }
  int websocket_port() const { return std::stoi(read_text(directory_ / "ws_port")); }
  pid_t pid() const { return pid_; }  // -1 once it has ended
  bool running() const { return pid_ > 0 && port_ > 0; }
  std::string log() const { return read_text(log_file_); }
  // The log once it holds every one of `texts`, or as it is after 30 s. The daemon writes some
  // lines after the client has seen what they record (a TLS alert is sent before the handshake
  // failure is logged; a cut socket closes before its line is written).
  std::string log_with(std::initializer_list<std::string> texts) const {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    for (;;) {
      std::string text = log();
      const bool all = std::all_of(texts.begin(), texts.end(), [&](const std::string& needle) {
        return text.find(needle) != std::string::npos;
      });
      if (all || std::chrono::steady_clock::now() > deadline) return text;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  // The handle (protocol model_id) of the model called `name` the daemon holds since start-up
  // (the default "mannequin"), from its start-up log: handles come from content ids
  // (server/models/content_id.h), so a test cannot know them beforehand. 0 when not logged.
  std::uint32_t model_id(const std::string& name = "mannequin") const {
    std::istringstream lines(log());
    for (std::string line; std::getline(lines, line);) {
      const nlohmann::json event = nlohmann::json::parse(line, nullptr, false);
      if (event.is_object() && event.value("name", "") == name && event.contains("model") &&
          (event.value("event", "") == "model_loaded" ||
           event.value("event", "") == "model_restored"))
        return event["model"].get<std::uint32_t>();
    }
    return 0;
  }

  void signal(int number) { kill(pid_, number); }
  // Waits for the process to end; its exit code, or -signal when killed, or nullopt on timeout.
  std::optional<int> wait(std::chrono::seconds timeout = std::chrono::seconds(30)) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return std::nullopt;
  }

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
  FrameClient(int port, const WebSocketUpgrade& upgrade)
      : FrameClient(port, upgrade.receive_buffer_bytes) {
    if (!upgrade.tls_ca.empty() && !start_tls(upgrade.tls_ca)) return;
    websocket_ = std::make_unique<server::WebSocketSession>(server::WebSocketSession::Role::kClient,
                                                            std::vector<std::string>{}, 1u << 30);
    websocket_->start_client("127.0.0.1:" + std::to_string(port), upgrade.origin);
    flush_websocket();
    while (websocket_->state() == server::WebSocketSession::State::kHandshaking &&
           read_websocket()) {
    }
  }

  // receive_buffer_bytes > 0: SO_RCVBUF set before connecting (a client that reads slowly).
  explicit FrameClient(int port, int receive_buffer_bytes = 0) {
    fd_ = socket(AF_INET, SOCK_STREAM, 0);
    if (receive_buffer_bytes > 0)
      setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &receive_buffer_bytes, sizeof(receive_buffer_bytes));
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<std::uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = connect(fd_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) == 0;
    const int one = 1;
    setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
    set_timeout();
  }
  explicit FrameClient(const fs::path& unix_socket) {
    fd_ = socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::strncpy(address.sun_path, unix_socket.c_str(), sizeof(address.sun_path) - 1);
    connected_ = connect(fd_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) == 0;
    set_timeout();
  }
  ~FrameClient() { close(fd_); }
  FrameClient(const FrameClient&) = delete;
  FrameClient& operator=(const FrameClient&) = delete;

  bool connected() const { return connected_; }
  // The socket, for a test's own recvmsg (a descriptor passed with a reply).
  int fd() const { return fd_; }

  // On WebSocket: one binary message.
  bool send_bytes(std::span<const std::uint8_t> bytes) {
    if (websocket_) {
      websocket_->send_binary(bytes.data(), bytes.size());
      return flush_websocket();
    }
    return send_raw(bytes);
  }

  // WebSocket only: a text message (what a browser's send(string) makes).
  bool send_text(const std::string& text) {
    websocket_->send_text(text);
    return flush_websocket();
  }

  bool send_raw(std::span<const std::uint8_t> bytes) {
    if (tls_) {
      return bytes.empty() || SSL_write(tls_.get(), bytes.data(), static_cast<int>(bytes.size())) ==
                                  static_cast<int>(bytes.size());
    }
    std::size_t sent = 0;
    while (sent < bytes.size()) {
      const ssize_t n = ::send(fd_, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
      if (n <= 0) return false;
      sent += static_cast<std::size_t>(n);
    }
    return true;
  }

  // The next frame's Message, or nullptr at end of stream / timeout (valid until next call).
  const protocol::Message* receive() {
    std::uint8_t prefix[4];
    if (!receive_exactly(prefix, 4)) return nullptr;
    std::uint32_t length = 0;
    std::memcpy(&length, prefix, 4);
    storage_.assign((4 + length + 7) / 8, 0);
    auto* bytes = reinterpret_cast<std::uint8_t*>(storage_.data());
    std::memcpy(bytes, prefix, 4);
    if (!receive_exactly(bytes + 4, length)) return nullptr;
    last_frame_ = {bytes, 4 + length};
    flatbuffers::Verifier verifier(bytes, 4 + length);
    if (!protocol::VerifySizePrefixedMessageBuffer(verifier)) {
      ADD_FAILURE() << "the server sent a frame that does not verify";
      return nullptr;
    }
    return protocol::GetSizePrefixedMessage(bytes);
  }

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
    if (body == nullptr) {
      const protocol::Error* error = message->body_as_Error();
      ADD_FAILURE() << "expected " << protocol::EnumNameBody(protocol::BodyTraits<T>::enum_value)
                    << ", got " << protocol::EnumNameBody(message->body_type())
                    << (error ? " " + std::string(protocol::EnumNameErrorCode(error->code())) +
                                    ": " + error->message()->str()
                              : std::string());
    }
    return body;
  }

  // True when the server has closed the connection (a read returns end of stream; on
  // WebSocket after its close frame, if any).
  bool closed_by_server() {
    if (websocket_) {
      while (read_websocket()) {
      }
      return socket_ended_;
    }
    std::uint8_t byte;
    return recv(fd_, &byte, 1, 0) == 0;
  }

  // Everything the server sends until it closes (an HTTP response to a request on the
  // WebSocket port), as text.
  std::string receive_text_until_closed() {
    std::string text;
    char chunk[4096];
    for (ssize_t n; (n = recv(fd_, chunk, sizeof(chunk), 0)) > 0;) text.append(chunk, n);
    return text;
  }

  // WebSocket only: the session (its close code, text messages), and the upgrade's HTTP status.
  server::WebSocketSession& websocket() { return *websocket_; }
  int websocket_status() const { return websocket_ ? websocket_->http_status() : 0; }
  // wss: the TLS handshake failed (or was not tried).
  bool tls_failed() const { return tls_ == nullptr; }

  const protocol::Welcome* hello(
      const std::string& token, protocol::PoseDelivery delivery = protocol::PoseDelivery::InOrder) {
    flatbuffers::FlatBufferBuilder builder;
    send_bytes(protocol::build_hello(builder, token, "server_test", delivery, 1));
    return receive_as<protocol::Welcome>();
  }

 private:
  void set_timeout() {
    timeval timeout{kTimeoutSeconds, 0};
    setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof(timeout));
  }
  bool receive_exactly(std::uint8_t* out, std::size_t count) {
    if (websocket_) {
      std::vector<std::uint8_t>& payload = websocket_->payload();
      while (payload.size() - payload_taken_ < count) {
        if (!read_websocket()) return false;
      }
      std::memcpy(out, payload.data() + payload_taken_, count);
      payload_taken_ += count;
      if (payload_taken_ == payload.size()) {
        payload.clear();
        payload_taken_ = 0;
      }
      return true;
    }
    std::size_t got = 0;
    while (got < count) {
      const ssize_t n = recv(fd_, out + got, count - got, 0);
      if (n <= 0) return false;
      got += static_cast<std::size_t>(n);
    }
    return true;
  }

  // WebSocket: what the session has for the server (its messages, pongs, close frames).
  bool flush_websocket() {
    std::vector<std::uint8_t> bytes;
    bytes.swap(websocket_->outgoing());
    return send_raw(bytes);
  }
  // WebSocket: one read from the socket into the session; false at its end or on timeout.
  bool read_websocket() {
    std::uint8_t chunk[64 * 1024];
    const ssize_t n =
        tls_ ? SSL_read(tls_.get(), chunk, sizeof(chunk)) : recv(fd_, chunk, sizeof(chunk), 0);
    if (n <= 0) {
      socket_ended_ = n == 0;
      return false;
    }
    websocket_->receive(chunk, static_cast<std::size_t>(n));
    flush_websocket();
    return true;
  }

  // wss: a blocking TLS client on the socket (OpenSSL), checking the server's certificate.
  bool start_tls(const std::string& ca_file) {
    tls_context_.reset(SSL_CTX_new(TLS_client_method()));
    SSL_CTX_set_verify(tls_context_.get(), SSL_VERIFY_PEER, nullptr);
    if (SSL_CTX_load_verify_locations(tls_context_.get(), ca_file.c_str(), nullptr) != 1)
      return false;
    tls_.reset(SSL_new(tls_context_.get()));
    SSL_set_fd(tls_.get(), fd_);
    if (SSL_connect(tls_.get()) != 1) tls_.reset();
    return tls_ != nullptr;
  }

  int fd_ = -1;
  bool connected_ = false;
  std::unique_ptr<SSL_CTX, decltype(&SSL_CTX_free)> tls_context_{nullptr, SSL_CTX_free};
  std::unique_ptr<SSL, decltype(&SSL_free)> tls_{nullptr, SSL_free};
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
  void SetUp() override {
    clip_ = fs::path(SWEEPD_SHARED_DATA) / "motion" / "cmu_01_01.bvh";
    if (!fs::exists(clip_)) GTEST_SKIP() << "shared data absent: " << clip_;
    directory_ = fresh_directory(directory_name_);
    daemon_ =
        std::make_unique<DaemonProcess>(directory_, std::vector<std::string>{"--token", "t0k"});
    ASSERT_TRUE(daemon_->running()) << daemon_->log();
  }
  void TearDown() override {
    daemon_.reset();
    if (!directory_.empty()) fs::remove_all(directory_);
  }

  fs::path clip_, directory_;
  std::unique_ptr<DaemonProcess> daemon_;

 private:
  std::string directory_name_;
};

}  // namespace sweepd::test
