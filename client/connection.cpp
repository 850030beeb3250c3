#include "client/connection.h"

#include <sys/socket.h>

#include <cstring>
#include <optional>

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
    : Connection(split_address(address).first, split_address(address).second, tls) {}

Connection::Connection(const std::string& host, const std::string& port, const ClientTls& tls)
    : address_(host + ":" + port), allow_plaintext_(tls.allow_plaintext), socket_(io_) {
  try {
    asio::connect(socket_, asio::ip::tcp::resolver(io_).resolve(host, port));
  } catch (const std::system_error& error) {
    throw ConnectionLost("cannot connect to sweepd at " + address_ + ": " + error.what());
  }
  socket_.set_option(asio::ip::tcp::no_delay(true));
  if (tls.enabled)
    tls_ = std::make_unique<TlsChannel>(socket_.native_handle(), host, address_, tls);
}

const pb::Welcome& Connection::hello(std::string_view token, std::string_view client_name,
                                     pb::PoseDelivery delivery) {
  std::error_code unknown;
  if (!token.empty() && !tls_ && !allow_plaintext_ &&
      !socket_.remote_endpoint(unknown).address().is_loopback()) {
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
    throw ConnectionLost(
        std::string(error.what()) +
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

const pb::Message& Connection::receive() {
  std::uint32_t length = 0;
  read_exactly({reinterpret_cast<std::uint8_t*>(&length), 4});
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
      asio::read(socket_, asio::buffer(bytes.data(), bytes.size()));
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

void Connection::close(std::string_view reason) {
  builder_.Clear();
  send(pb::finish_message(builder_, pb::CreateBye(builder_, builder_.CreateString(reason))));
  if (tls_) tls_->close();
  std::error_code ignored;
  socket_.shutdown(asio::ip::tcp::socket::shutdown_both, ignored);
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
