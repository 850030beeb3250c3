// The definitions of tests/server/daemon_process.h (the library test_daemon_process).
#include "tests/server/daemon_process.h"

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <openssl/ssl.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "tests/server/loopback_port.h"

namespace sweepd::test {

std::string read_text(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<std::uint8_t> read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<std::string> with(std::vector<std::string> args, const std::vector<std::string>& more) {
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

namespace {

// The store of a daemon that made the test mannequin (kTestMannequinVertices) and stopped: made
// once per build of sweepd (the directory is named by the binary's modification time, so a
// rebuilt daemon makes it again) by the first test that needs it, then copied into the fresh
// store of every daemon that gets the test mannequin. Making the mannequin takes 3 s of CPU
// under ASan (0.3 s in Release), and about 200 daemon starts there did it; restoring it from a
// store is what sweepd does at every restart (server/models/model_service.cpp), and the
// restored model is the made one byte for byte (same content id, same stored binding).
// Several test processes may make it at once: each makes its own and renames it into place,
// and the first rename wins.
fs::path test_mannequin_store() {
  const auto stamp = static_cast<std::uint64_t>(
      fs::last_write_time(SWEEPD_DAEMON).time_since_epoch().count());
  const fs::path cache = SWEEPD_TEST_CACHE_DIR;
  const std::string prefix = "mannequin-" + std::to_string(kTestMannequinVertices) + "-";
  const fs::path made = cache / (prefix + std::to_string(stamp));
  if (fs::exists(made)) return made;
  std::error_code ignored;  // the stores of earlier builds of sweepd, if any
  for (const fs::directory_entry& old : fs::directory_iterator(cache, ignored))
    if (old.path().filename().string().starts_with(prefix)) fs::remove_all(old.path(), ignored);
  const ScratchDirectory scratch("test_mannequin_store");
  {
    DaemonProcess maker(scratch.path(),
                        {"--mannequin-vertices", std::to_string(kTestMannequinVertices)});
    if (!maker.running()) return {};
    maker.signal(SIGTERM);
    if (maker.wait() != 0) return {};
  }
  fs::create_directories(made.parent_path());
  std::error_code lost_the_race;  // another test renamed its copy into place first
  fs::rename(scratch.path() / "store", made, lost_the_race);
  return made;
}

}  // namespace

DaemonProcess::DaemonProcess(const fs::path& directory, std::vector<std::string> extra_args,
                             std::vector<std::string> wrapper)
    : directory_(directory) {
  const fs::path port_file = directory / "port";
  fs::remove(port_file);
  const fs::path store = directory / "store";
  std::vector<std::string> args = {SWEEPD_DAEMON, "--port", "0", "--port-file", port_file,
                                   "--store-dir", store};
  args.insert(args.end(), extra_args.begin(), extra_args.end());
  // Most daemon tests never measure the default model, and under ASan the 20k default takes
  // seconds to make and bind at every start: a daemon not told the size gets a 2k mannequin,
  // restored from a store that holds it when its own store is new (test_mannequin_store). A
  // test that measures the default model passes --mannequin-vertices itself.
  const auto given = [&extra_args](const char* flag) {
    return std::ranges::find(extra_args, flag) != extra_args.end();
  };
  if (!given("--mannequin-vertices") && !given("--config")) {
    args.insert(args.end(), {"--mannequin-vertices", std::to_string(kTestMannequinVertices)});
    if (!given("--model-dir") && !fs::exists(store))
      if (const fs::path made = test_mannequin_store(); !made.empty())
        fs::copy(made, store, fs::copy_options::recursive);
  }
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

DaemonProcess::~DaemonProcess() {
  if (pid_ > 0) {
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
  }
}

std::vector<std::string> DaemonProcess::websocket_flags(const fs::path& directory) {
  return {"--ws-listen", "127.0.0.1:0", "--ws-port-file", (directory / "ws_port").string()};
}

int DaemonProcess::websocket_port() const { return std::stoi(read_text(directory_ / "ws_port")); }

std::string DaemonProcess::log() const { return read_text(log_file_); }

std::string DaemonProcess::log_with(std::initializer_list<std::string> texts) const {
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

std::uint32_t DaemonProcess::model_id(const std::string& name) const {
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

void DaemonProcess::signal(int number) { kill(pid_, number); }

std::optional<int> DaemonProcess::wait(std::chrono::seconds timeout) {
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

void FrameClient::TlsFree::operator()(SSL_CTX* context) const { SSL_CTX_free(context); }
void FrameClient::TlsFree::operator()(SSL* tls) const { SSL_free(tls); }

FrameClient::FrameClient(int port, const WebSocketUpgrade& upgrade)
    : FrameClient(port, upgrade.receive_buffer_bytes) {
  if (!upgrade.tls_ca.empty() && !start_tls(upgrade.tls_ca)) return;
  websocket_ = std::make_unique<server::WebSocketSession>(server::WebSocketSession::Role::kClient,
                                                          std::vector<std::string>{}, 1u << 30);
  websocket_->start_client("127.0.0.1:" + std::to_string(port), upgrade.origin);
  flush_websocket();
  while (websocket_->state() == server::WebSocketSession::State::kHandshaking && read_websocket()) {
  }
}

FrameClient::FrameClient(int port, int receive_buffer_bytes) {
  fd_ = socket(AF_INET, SOCK_STREAM, 0);
  if (receive_buffer_bytes > 0)
    setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &receive_buffer_bytes, sizeof(receive_buffer_bytes));
  const sockaddr_in address = loopback_address(port);
  connected_ = connect(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) == 0;
  const int one = 1;
  setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
  set_timeout();
}

FrameClient::FrameClient(const fs::path& unix_socket) {
  fd_ = socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::strncpy(address.sun_path, unix_socket.c_str(), sizeof(address.sun_path) - 1);
  connected_ = connect(fd_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) == 0;
  set_timeout();
}

FrameClient::~FrameClient() { close(fd_); }

bool FrameClient::send_bytes(std::span<const std::uint8_t> bytes) {
  if (websocket_) {
    websocket_->send_binary(bytes.data(), bytes.size());
    return flush_websocket();
  }
  return send_raw(bytes);
}

bool FrameClient::send_text(const std::string& text) {
  websocket_->send_text(text);
  return flush_websocket();
}

bool FrameClient::send_raw(std::span<const std::uint8_t> bytes) {
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

const protocol::Message* FrameClient::receive() {
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

std::string FrameClient::describe(const protocol::Message& message) {
  const protocol::Error* error = message.body_as_Error();
  return std::string(protocol::EnumNameBody(message.body_type())) +
         (error ? " " + std::string(protocol::EnumNameErrorCode(error->code())) + ": " +
                      error->message()->str()
                : std::string());
}

bool FrameClient::closed_by_server() {
  if (websocket_) {
    while (read_websocket()) {
    }
    return socket_ended_;
  }
  std::uint8_t byte;
  return recv(fd_, &byte, 1, 0) == 0;
}

std::string FrameClient::receive_text_until_closed() {
  std::string text;
  char chunk[4096];
  for (ssize_t n; (n = recv(fd_, chunk, sizeof(chunk), 0)) > 0;) text.append(chunk, n);
  return text;
}

const protocol::Welcome* FrameClient::hello(const std::string& token,
                                            protocol::PoseDelivery delivery) {
  flatbuffers::FlatBufferBuilder builder;
  send_bytes(protocol::build_hello(builder, token, "server_test", delivery, 1));
  return receive_as<protocol::Welcome>();
}

void FrameClient::set_timeout() {
  timeval timeout{kTimeoutSeconds, 0};
  setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof(timeout));
}

bool FrameClient::receive_exactly(std::uint8_t* out, std::size_t count) {
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

bool FrameClient::flush_websocket() {
  std::vector<std::uint8_t> bytes;
  bytes.swap(websocket_->outgoing());
  return send_raw(bytes);
}

bool FrameClient::read_websocket() {
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

bool FrameClient::start_tls(const std::string& ca_file) {
  tls_context_.reset(SSL_CTX_new(TLS_client_method()));
  SSL_CTX_set_verify(tls_context_.get(), SSL_VERIFY_PEER, nullptr);
  if (SSL_CTX_load_verify_locations(tls_context_.get(), ca_file.c_str(), nullptr) != 1)
    return false;
  tls_.reset(SSL_new(tls_context_.get()));
  SSL_set_fd(tls_.get(), fd_);
  if (SSL_connect(tls_.get()) != 1) tls_.reset();
  return tls_ != nullptr;
}

void ClipClientTest::SetUp() {
  clip_ = fs::path(SWEEPD_SHARED_DATA) / "motion" / "cmu_01_01.bvh";
  if (!fs::exists(clip_)) GTEST_SKIP() << "shared data absent: " << clip_;
  directory_ = fresh_directory(directory_name_);
  daemon_ = std::make_unique<DaemonProcess>(directory_, std::vector<std::string>{"--token", "t0k"});
  ASSERT_TRUE(daemon_->running()) << daemon_->log();
}

void ClipClientTest::TearDown() {
  daemon_.reset();
  if (!directory_.empty()) fs::remove_all(directory_);
}

}  // namespace sweepd::test
