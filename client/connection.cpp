#include "client/connection.h"

#include <sys/mman.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <optional>

#include "protocol/descriptor_passing.h"

namespace sweepd::client {

namespace pb = sweepd::protocol;

namespace {

std::pair<std::string, std::string> split_address(const std::string& address) {
  const std::size_t colon = address.rfind(':');
  if (colon == std::string::npos || colon + 1 == address.size()) {
    throw std::invalid_argument("server address '" + address + "' is not HOST:PORT");
  }
  std::string host = address.substr(0, colon);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') {
    host = host.substr(1, host.size() - 2);
  }
  return {host.empty() ? "127.0.0.1" : host, address.substr(colon + 1)};
}

}  // namespace

ServerError::ServerError(pb::ErrorCode code, const std::string& message)
    : std::runtime_error(std::string("server error ") + pb::EnumNameErrorCode(code) + ": " +
                         message),
      code_(code) {}

Connection::Connection(const std::string& address, const ClientTls& tls)
    : address_(address), allow_plaintext_(tls.allow_plaintext), socket_(io_) {
  if (address.starts_with("unix:")) {
    if (tls.enabled) {
      throw std::invalid_argument("TLS is for TCP; " + address + " is a Unix socket");
    }
    connect_unix(address.substr(5));
  } else {
    const auto [host, port] = split_address(address);
    address_ = host + ":" + port;
    connect_tcp(host, port, tls);
  }
}

Connection::Connection(const std::string& host, const std::string& port, const ClientTls& tls)
    : address_(host + ":" + port), allow_plaintext_(tls.allow_plaintext), socket_(io_) {
  connect_tcp(host, port, tls);
}

Connection::~Connection() {
  if (!shared_.empty()) munmap(const_cast<std::uint8_t*>(shared_.data()), shared_.size());
}

void Connection::connect_tcp(const std::string& host, const std::string& port,
                             const ClientTls& tls) {
  asio::ip::tcp::socket tcp(io_);
  try {
    asio::connect(tcp, asio::ip::tcp::resolver(io_).resolve(host, port));
  } catch (const std::system_error& error) {
    throw ConnectionLost("cannot connect to sweepd at " + address_ + ": " + error.what());
  }
  tcp.set_option(asio::ip::tcp::no_delay(true));
  std::error_code unknown;
  local_peer_ = tcp.remote_endpoint(unknown).address().is_loopback();
  const asio::ip::tcp protocol = tcp.local_endpoint().protocol();
  socket_ = asio::generic::stream_protocol::socket(
      io_, asio::generic::stream_protocol(protocol.family(), protocol.protocol()), tcp.release());
  if (tls.enabled)
    tls_ = std::make_unique<TlsChannel>(socket_.native_handle(), host, address_, tls);
}

void Connection::connect_unix(const std::string& path) {
  asio::local::stream_protocol::socket local(io_);
  try {
    local.connect(asio::local::stream_protocol::endpoint(path));
  } catch (const std::system_error& error) {
    throw ConnectionLost("cannot connect to sweepd at " + address_ + ": " + error.what());
  }
  local_peer_ = true;
  socket_ = asio::generic::stream_protocol::socket(io_, asio::generic::stream_protocol(AF_UNIX, 0),
                                                   local.release());
}

const pb::Welcome& Connection::hello(std::string_view token, std::string_view client_name,
                                     pb::PoseDelivery delivery) {
  if (!token.empty() && !tls_ && !allow_plaintext_ && !local_peer_) {
    throw std::runtime_error("sweepd at " + address_ +
                             ": refusing to send the token over plain TCP to a host that is not "
                             "loopback; connect with --tls (sweepd's --tls-cert/--tls-key), or "
                             "pass --allow-plaintext on a private network");
  }
  builder_.Clear();
  send(pb::build_hello(builder_, token, client_name, delivery));
  try {
    return expect<pb::Welcome>();
  } catch (const ServerError&) {
    throw;
  } catch (const ConnectionLost& error) {
    if (tls_) throw;
    // A TLS listener drops a plaintext Hello without a reply.
    throw ConnectionLost(std::string(error.what()) +
                         " (closed before Welcome: if sweepd has --tls-cert, connect with --tls)");
  }
}

const pb::ModelInfo& Connection::load_model(const std::string& name,
                                            std::span<const std::uint8_t> glb) {
  builder_.Clear();
  const auto bytes = glb.empty() ? 0 : builder_.CreateVector(glb.data(), glb.size());
  send(pb::finish_message(builder_,
                          pb::CreateLoadModel(builder_, builder_.CreateString(name), bytes)));
  return expect<pb::ModelInfo>();
}

void Connection::send(std::span<const std::uint8_t> frame) {
  if (tls_) {
    tls_->write_all(frame);
    return;
  }
  try {
    asio::write(socket_, asio::buffer(frame.data(), frame.size()));
  } catch (const std::system_error& error) {
    throw ConnectionLost("sending to sweepd at " + address_ + ": " + error.what());
  }
}

std::span<const std::uint8_t> Connection::map_shared_memory(std::uint64_t bytes) {
  if (!shared_.empty()) {
    throw std::logic_error("sweepd at " + address_ + ": this connection has mapped its region");
  }
  builder_.Clear();
  send(pb::finish_message(builder_, pb::CreateMapSharedMemory(builder_, bytes)));
  int descriptor = -1;
  const pb::Message& message = receive(&descriptor);
  auto closing = [descriptor]() {
    if (descriptor >= 0) ::close(descriptor);
  };
  try {
    throw_if_error(message);
  } catch (...) {
    closing();
    throw;
  }
  const pb::SharedMemory* granted = message.body_as_SharedMemory();
  struct stat status {};
  if (granted == nullptr || granted->bytes() != bytes || descriptor < 0 ||
      fstat(descriptor, &status) != 0 || static_cast<std::uint64_t>(status.st_size) < bytes) {
    closing();
    throw std::runtime_error("sweepd at " + address_ +
                             " answered MapSharedMemory without a region of " +
                             std::to_string(bytes) + " bytes");
  }
  void* memory = mmap(nullptr, bytes, PROT_READ, MAP_SHARED, descriptor, 0);
  closing();  // the mapping keeps the region
  if (memory == MAP_FAILED) {
    throw std::system_error(errno, std::generic_category(), "mapping sweepd's shared region");
  }
  shared_ = {static_cast<const std::uint8_t*>(memory), bytes};
  return shared_;
}

std::span<const float> Connection::shared_floats(const pb::PosedVertices& reply,
                                                 std::size_t first) const {
  // The reply's offset is the server's word: checked against the region without overflowing.
  const std::size_t count = 3 * std::size_t{reply.vertex_count()};
  const std::uint64_t start = reply.shared_offset();
  const std::uint64_t skip = first * count * sizeof(float);
  if (!reply.in_shared_memory() || start % sizeof(float) != 0 || start > shared_.size() ||
      skip > shared_.size() - start || count > (shared_.size() - start - skip) / sizeof(float)) {
    return {};
  }
  const std::uint64_t offset = start + skip;
  return {reinterpret_cast<const float*>(shared_.data() + offset), count};
}

std::span<const float> Connection::shared_positions(const pb::PosedVertices& reply) const {
  return shared_floats(reply, 0);
}

std::span<const float> Connection::shared_normals(const pb::PosedVertices& reply) const {
  return shared_floats(reply, 1);
}

const pb::Message& Connection::receive(int* descriptor) {
  std::uint32_t length = 0;
  auto* prefix = reinterpret_cast<std::uint8_t*>(&length);
  std::size_t have = 0;
  if (descriptor != nullptr && !tls_) {
    // The descriptor comes with the frame's first bytes: read them with room for it. (Over TLS
    // none comes: the server refuses MapSharedMemory there, and its Error is read through TLS.)
    try {
      have = pb::receive_with_descriptor(socket_.native_handle(), {prefix, 4}, *descriptor);
    } catch (const std::system_error& error) {
      throw ConnectionLost("reading from sweepd at " + address_ + ": " + error.what());
    }
    if (have == 0) throw ConnectionLost("sweepd at " + address_ + " closed the connection");
  }
  read_exactly({prefix + have, 4 - have});
  storage_.resize((4 + std::size_t{length} + 7) / 8);
  auto* bytes = reinterpret_cast<std::uint8_t*>(storage_.data());
  read_exactly({bytes + 4, length});
  std::memcpy(bytes, &length, 4);
  flatbuffers::Verifier verifier(bytes, 4 + std::size_t{length});
  if (!pb::VerifySizePrefixedMessageBuffer(verifier)) {
    throw std::runtime_error("sweepd at " + address_ + " sent a frame that does not verify");
  }
  return *pb::GetSizePrefixedMessage(bytes);
}

// A blocking read; with a timeout, an asynchronous one run for at most that long (Asio's way
// to bound a read), or for TLS a wait on the socket that gives up after it.
void Connection::read_exactly(std::span<std::uint8_t> bytes) {
  if (tls_) {
    tls_->read_exactly(bytes, receive_timeout_);
    return;
  }
  try {
    if (receive_timeout_.count() == 0) {
      const std::size_t polled = receive_spin_.count() > 0 ? read_spinning(bytes) : 0;
      asio::read(socket_, asio::buffer(bytes.data() + polled, bytes.size() - polled));
      return;
    }
    std::optional<std::error_code> result;
    asio::async_read(socket_, asio::buffer(bytes.data(), bytes.size()),
                     [&result](const std::error_code& error, std::size_t) { result = error; });
    io_.restart();
    io_.run_for(receive_timeout_);
    if (!result) {
      std::error_code ignored;
      socket_.close(ignored);  // cancels the read; its handler runs with operation_aborted
      io_.restart();
      io_.run();
      throw ReceiveTimeout("sweepd at " + address_ + " sent nothing for " +
                           std::to_string(receive_timeout_.count()) + " ms");
    }
    if (*result) throw std::system_error(*result);
  } catch (const std::system_error& error) {
    throw ConnectionLost("reading from sweepd at " + address_ + ": " + error.what());
  }
}

std::size_t Connection::read_spinning(std::span<std::uint8_t> bytes) {
  const auto until = std::chrono::steady_clock::now() + receive_spin_;
  std::size_t read = 0;
  while (read < bytes.size()) {
    const ssize_t n =
        ::recv(socket_.native_handle(), bytes.data() + read, bytes.size() - read, MSG_DONTWAIT);
    if (n > 0) {
      read += static_cast<std::size_t>(n);
    } else if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) ||
               std::chrono::steady_clock::now() >= until) {
      break;  // the blocking read that follows reports the end or the error, or waits
    }
  }
  return read;
}

void Connection::close(std::string_view reason) {
  builder_.Clear();
  send(pb::finish_message(builder_, pb::CreateBye(builder_, builder_.CreateString(reason))));
  if (tls_) tls_->close();
  std::error_code ignored;
  socket_.shutdown(asio::socket_base::shutdown_both, ignored);
  socket_.close(ignored);
}

void Connection::abort() {
  // shutdown(2), not asio's: asio's socket object is not for use by two threads at once.
  ::shutdown(socket_.native_handle(), SHUT_RDWR);
}

void Connection::throw_if_error(const pb::Message& message) {
  if (const pb::Error* error = message.body_as_Error()) {
    throw ServerError(error->code(), error->message() ? error->message()->str() : "");
  }
}

}  // namespace sweepd::client
