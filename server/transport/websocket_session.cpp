// Compiled as C++17 (websocketpp 0.8.2 is not C++20 code): see websocket_session.h.
#include "server/transport/websocket_session.h"

#include <websocketpp/client.hpp>
#include <websocketpp/config/core.hpp>
#include <websocketpp/config/core_client.hpp>
#include <websocketpp/server.hpp>

#include "server/transport/origin_policy.h"

namespace sweepd::server {
namespace {

namespace ws = websocketpp;

// websocketpp's own logs off at compile time: sweepd logs each outcome as one JSON line.
template <typename Base>
struct Quiet : Base {
  using type = Quiet;
  static const ws::log::level elog_level = ws::log::elevel::none;
  static const ws::log::level alog_level = ws::log::alevel::none;
};
using ServerEndpoint = ws::server<Quiet<ws::config::core>>;
using ClientEndpoint = ws::client<Quiet<ws::config::core_client>>;

// Whether the peer's close frame arrived: websocketpp keeps 1006 (abnormal close, a code no
// peer may send) as the peer's code until then.
template <typename Connection>
bool close_received(const Connection& connection) {
  return connection.get_remote_close_code() != ws::close::status::abnormal_close;
}

// What both roles keep: bytes out, payloads in, and how the session ended.
struct Traffic {
  std::vector<std::uint8_t> outgoing, payload;
  std::size_t pending_bytes = 0;  // received since the last whole message or control frame
  std::string failure;
  bool open = false, ended = false;
};

// Wires one websocketpp connection to `traffic`.
template <typename Connection>
void wire(Connection& connection, Traffic& traffic) {
  using Message = typename Connection::element_type::message_ptr;
  connection->set_write_handler([&traffic](ws::connection_hdl, const char* bytes, std::size_t n) {
    traffic.outgoing.insert(traffic.outgoing.end(), bytes, bytes + n);
    return std::error_code();
  });
  connection->set_shutdown_handler([&traffic](ws::connection_hdl) {
    traffic.ended = true;
    return std::error_code();
  });
  connection->set_open_handler([&traffic](ws::connection_hdl) {
    traffic.open = true;
    traffic.pending_bytes = 0;  // the upgrade's bytes are no message
  });
  connection->set_close_handler([&traffic](ws::connection_hdl) { traffic.ended = true; });
  Connection* self = &connection;
  connection->set_fail_handler([&traffic, self](ws::connection_hdl) {
    traffic.ended = true;
    if (!traffic.failure.empty()) return;  // the Origin refusal already said why
    const int status = (*self)->get_response_code();
    const std::string reason = (*self)->get_ec().message();
    traffic.failure = traffic.open ? "WebSocket failed: " + reason
                                   : "WebSocket handshake failed: HTTP " + std::to_string(status) +
                                         " (" + reason + ")";
  });
  connection->set_ping_handler([&traffic](ws::connection_hdl, std::string) {
    traffic.pending_bytes = 0;
    return true;  // answered with a pong
  });
  connection->set_pong_handler(
      [&traffic](ws::connection_hdl, std::string) { traffic.pending_bytes = 0; });
  connection->set_message_handler([&traffic, self](ws::connection_hdl, Message message) {
    traffic.pending_bytes = 0;
    if (message->get_opcode() != ws::frame::opcode::binary) {
      traffic.failure =
          "a text message: sweepd's frames travel as binary WebSocket messages, one frame each";
      std::error_code ignored;
      (*self)->close(ws::close::status::unsupported_data, "binary messages only", ignored);
      return;
    }
    const std::string& bytes = message->get_payload();
    traffic.payload.insert(traffic.payload.end(), bytes.begin(), bytes.end());
  });
}

}  // namespace

struct WebSocketSession::Endpoint {
  Endpoint(std::vector<std::string> origins, std::size_t max_message)
      : allowed_origins(std::move(origins)), max_message_bytes(max_message) {}

  std::vector<std::string> allowed_origins;
  std::size_t max_message_bytes;
  Traffic traffic;
  ServerEndpoint server;
  ServerEndpoint::connection_ptr server_connection;
  ClientEndpoint client;
  ClientEndpoint::connection_ptr client_connection;

  template <typename Action>
  void on_connection(Action action) {
    if (server_connection) action(server_connection);
    if (client_connection) action(client_connection);
  }
};

WebSocketSession::WebSocketSession(Role role, std::vector<std::string> allowed_origins,
                                   std::size_t max_message_bytes)
    : endpoint_(std::make_unique<Endpoint>(std::move(allowed_origins), max_message_bytes)) {
  if (role == Role::kClient) return;
  Endpoint& e = *endpoint_;
  e.server.set_user_agent("sweepd");
  e.server_connection = e.server.get_connection();
  wire(e.server_connection, e.traffic);
  e.server_connection->set_max_message_size(max_message_bytes);
  ServerEndpoint::connection_ptr* connection = &e.server_connection;
  e.server_connection->set_validate_handler([&e, connection](ws::connection_hdl) {
    const std::string refusal =
        origin_refusal((*connection)->get_request_header("Origin"),
                       (*connection)->get_request_header("Host"), e.allowed_origins);
    if (refusal.empty()) return true;
    e.traffic.failure = "WebSocket handshake failed: HTTP 403 (" + refusal + ")";
    (*connection)->set_status(ws::http::status_code::forbidden, refusal);
    return false;
  });
  e.server_connection->start();
}

// websocketpp's iostream transport keeps a waiting read's handler, which holds the connection's
// own shared_ptr: a session that ends without its last read answered (a peer that vanished, a
// refused or broken handshake) would keep its connection alive forever (about 20 KiB each).
// eof() answers that read, and the connection ends and lets go of itself.
WebSocketSession::~WebSocketSession() {
  endpoint_->on_connection([](auto& connection) { connection->eof(); });
}

void WebSocketSession::start_client(const std::string& host, const std::string& origin) {
  Endpoint& e = *endpoint_;
  std::error_code error;
  e.client.set_user_agent("sweepd-test-client");
  e.client_connection = e.client.get_connection("ws://" + host + "/", error);
  if (error) {
    e.traffic.failure = "WebSocket client: " + error.message();
    e.traffic.ended = true;
    return;
  }
  wire(e.client_connection, e.traffic);
  e.client_connection->set_max_message_size(e.max_message_bytes);
  if (!origin.empty()) e.client_connection->replace_header("Origin", origin);
  e.client.connect(e.client_connection);
}

void WebSocketSession::receive(const std::uint8_t* bytes, std::size_t count) {
  endpoint_->traffic.pending_bytes += count;
  const char* chars = reinterpret_cast<const char*>(bytes);
  endpoint_->on_connection(
      [chars, count](auto& connection) { connection->read_all(chars, count); });
}

void WebSocketSession::send_binary(const std::uint8_t* bytes, std::size_t count) {
  endpoint_->on_connection([bytes, count](auto& connection) {
    // Not open: nothing is sent, and the reader sees the end.
    static_cast<void>(connection->send(bytes, count, ws::frame::opcode::binary));
  });
}

void WebSocketSession::send_text(const std::string& text) {
  endpoint_->on_connection([&text](auto& connection) {
    static_cast<void>(connection->send(text, ws::frame::opcode::text));
  });
}

void WebSocketSession::close(std::uint16_t code, const std::string& reason) {
  endpoint_->on_connection([code, &reason](auto& connection) {
    std::error_code ignored;
    connection->close(code, reason, ignored);
  });
}

void WebSocketSession::set_max_message_bytes(std::size_t bytes) {
  endpoint_->max_message_bytes = bytes;
  endpoint_->on_connection([bytes](auto& connection) { connection->set_max_message_size(bytes); });
}

std::vector<std::uint8_t>& WebSocketSession::outgoing() { return endpoint_->traffic.outgoing; }
std::vector<std::uint8_t>& WebSocketSession::payload() { return endpoint_->traffic.payload; }

WebSocketSession::State WebSocketSession::state() const {
  const Traffic& traffic = endpoint_->traffic;
  if (traffic.ended || !traffic.failure.empty()) return State::kEnded;
  State state = traffic.open ? State::kOpen : State::kHandshaking;
  endpoint_->on_connection([&state](auto& connection) {
    if (connection->get_state() == ws::session::state::closing ||
        connection->get_state() == ws::session::state::closed)
      state = State::kEnded;
  });
  return state;
}

const std::string& WebSocketSession::failure() const {
  Traffic& traffic = endpoint_->traffic;
  // A close this side began (a message too big, a protocol violation) says why in its code.
  if (traffic.failure.empty() && traffic.open) {
    endpoint_->on_connection([&traffic](auto& connection) {
      const auto code = connection->get_local_close_code();
      if (connection->get_state() != ws::session::state::open && code != ws::close::status::blank &&
          code != ws::close::status::normal && !close_received(*connection))
        traffic.failure = "WebSocket closed with " + std::to_string(code) + " (" +
                          connection->get_local_close_reason() + ")";
    });
  }
  return traffic.failure;
}

bool WebSocketSession::mid_message() const { return endpoint_->traffic.pending_bytes > 0; }

std::uint16_t WebSocketSession::peer_close_code() const {
  std::uint16_t code = 0;
  endpoint_->on_connection([&code](auto& connection) {
    if (close_received(*connection)) code = connection->get_remote_close_code();
  });
  return code;
}

int WebSocketSession::http_status() const {
  int status = 0;
  endpoint_->on_connection(
      [&status](auto& connection) { status = connection->get_response_code(); });
  return status;
}

}  // namespace sweepd::server
