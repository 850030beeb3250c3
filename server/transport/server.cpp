#include "server/transport/server.h"

#include <csignal>
#include <future>
#include <thread>

#include "io/exr/exr_write.h"
#include "server/log_event.h"

namespace sweepd::server {
namespace {

// A reply of a large model (72k vertices: 0.85 MB of float32 positions, twice that with
// normals) fits the socket's send buffer whole, so one send hands it to the kernel. With the
// default (autotuned from 16 KiB) it went out in about 16 partial sends, each waiting for the
// I/O thread to be woken again. The kernel caps it at net.core.wmem_max; memory is used only
// while a client is slow to read.
constexpr int kSendBufferBytes = 4 << 20;
// After a failed accept (EMFILE, ENFILE, ENOBUFS), how long until the next is tried.
constexpr std::chrono::milliseconds kAcceptRetry{100};

std::size_t worker_count(const ServerConfig& config) {
  if (config.worker_threads > 0) return static_cast<std::size_t>(config.worker_threads);
  return std::max(1u, std::thread::hardware_concurrency());
}

}  // namespace

Server::Server(const ServerConfig& config, ModelService& models, Readiness& readiness,
               std::optional<asio::ssl::context> tls, GpuThread& gpu, CollisionService& collision)
    : config_(config),
      readiness_(readiness),
      worker_pool_(worker_count(config)),
      spare_cores_(static_cast<int>(worker_count(config))),
      workers_(worker_pool_, FairWorkQueue::steady_nanoseconds,
               std::chrono::microseconds(config.worker_spin_us), &spare_cores_),
      gpu_waiters_(worker_count(config)),
      position_maps_(config.position_maps != 0, gpu),
      contact_sheets_(position_maps_),
      clips_(config.max_clips, config.max_clip_bytes),
      buffer_budget_(config.max_buffered_bytes),
      work_budget_(config.work_budget_bytes, config.work_budget_client_bytes),
      // Enough idle builders for every worker's reply and the I/O thread's, and (added as
      // connections open) one for each connection's queued replies.
      builders_(2 * static_cast<std::size_t>(worker_count(config)) + 4),
      signals_(io_, SIGTERM, SIGINT),
      tls_(std::move(tls)),
      auth_backoff_(config.auth_free_failures, std::chrono::milliseconds(config.auth_backoff_ms),
                    std::chrono::milliseconds(config.auth_backoff_max_ms)),
      environment_{config,
                   models,
                   workers_,
                   spare_cores_,
                   gpu_waiters_,
                   position_maps_,
                   contact_sheets_,
                   clips_,
                   collision,
                   std::chrono::steady_clock::now(),
                   {},
                   {},
                   {},
                   buffer_budget_,
                   work_budget_,
                   builders_,
                   {},
                   auth_backoff_},
      strangers_(config.max_strangers, config.max_strangers_per_address),
      auth_burst_sweep_(io_) {
  if (!config.vmc_listens.empty()) {
    vmc_ = std::make_unique<VmcReceivers>(io_, models, config.vmc_listens);
    environment_.vmc = vmc_.get();
  }
  // Position maps' EXR compression runs on OpenEXR's process-wide pool: one thread per worker,
  // so that a ZIP frame is compressed in parallel scan-line blocks instead of on one core.
  io::set_exr_threads(static_cast<int>(worker_count(config)));
  environment_.on_close = [this](std::uint64_t id) {
    // Deferred: the connection may still be on the call stack.
    asio::post(io_, [this, id]() {
      const auto found = connections_.find(id);
      if (found == connections_.end()) return;
      environment_.traffic.closed_connections.add(found->second->counters());
      connections_.erase(found);
      builders_.set_connections(connections_.size());
    });
  };
  environment_.all_counters = [this]() {
    std::vector<ConnectionCounters> all;
    for (const auto& [id, connection] : connections_) all.push_back(connection->counters());
    return all;
  };
}

Server::~Server() {
  worker_pool_.join();
  gpu_waiters_.join();
}

int Server::listen_tcp(std::optional<asio::ip::tcp::acceptor>& acceptor, const std::string& address,
                       int port, const char* what) {
  try {
    const asio::ip::tcp::endpoint endpoint(asio::ip::make_address(address),
                                           static_cast<unsigned short>(port));
    acceptor.emplace(io_, endpoint, /*reuse_address=*/true);
    return acceptor->local_endpoint().port();
  } catch (const std::exception& error) {
    throw std::runtime_error(std::string("cannot listen") + what + " on " + address + ":" +
                             std::to_string(port) + " (" + error.what() + ")");
  }
}

int Server::open() {
  int port = 0;
  if (config_.port >= 0) {
    port = listen_tcp(tcp_acceptor_, config_.listen_address, config_.port, "");
    log_event("listening", {{"address", config_.listen_address},
                            {"port", port},
                            {"tls", tls_.has_value()},
                            {"client_certificates", !config_.tls_client_ca.empty()}});
    accept_next(*tcp_acceptor_);
  }
  if (config_.ws_port >= 0) {
    websocket_port_ =
        listen_tcp(websocket_acceptor_, config_.ws_address, config_.ws_port, " for WebSocket");
    log_event("listening", {{"address", config_.ws_address},
                            {"websocket_port", websocket_port_},
                            {"tls", tls_.has_value()},
                            {"allowed_origins", config_.ws_allowed_origins}});
    accept_next(*websocket_acceptor_);
  }
  if (vmc_) {
    vmc_ports_ = vmc_->open();
    vmc_->start();
  }
  if (!config_.unix_socket.empty()) {
    std::error_code ignored;
    std::filesystem::remove(config_.unix_socket, ignored);
    try {
      unix_acceptor_.emplace(io_, asio::local::stream_protocol::endpoint(config_.unix_socket));
    } catch (const std::exception& error) {
      throw std::runtime_error("cannot listen on Unix socket " + config_.unix_socket.string() +
                               " (" + error.what() + ")");
    }
    log_event("listening", {{"unix_socket", config_.unix_socket.string()}});
    accept_next(*unix_acceptor_);
  }
  return port;
}

template <typename Acceptor>
void Server::accept_next(Acceptor& acceptor) {
  acceptor.async_accept([this, &acceptor](std::error_code error,
                                          typename Acceptor::protocol_type::socket socket) {
    if (shutting_down_ || error == asio::error::operation_aborted) return;
    if (!error) {
      std::error_code ignored;
      socket.set_option(asio::socket_base::send_buffer_size(kSendBufferBytes), ignored);
      if constexpr (std::is_same_v<Acceptor, asio::ip::tcp::acceptor>) {
        socket.set_option(asio::ip::tcp::no_delay(true), ignored);
        const auto endpoint = socket.remote_endpoint(ignored);
        std::string address = endpoint.address().to_string();
        std::string peer = address + ":" + std::to_string(endpoint.port());
        std::unique_ptr<WebSocketSession> websocket;
        if (websocket_acceptor_ && &acceptor == &*websocket_acceptor_) {
          // Before Hello at most a Hello-sized message; Connection raises it after Hello.
          websocket = std::make_unique<WebSocketSession>(
              WebSocketSession::Role::kServer, config_.ws_allowed_origins,
              config_.max_hello_frame_bytes + protocol::kLengthPrefixBytes);
          peer = "ws:" + peer;
        }
        admit(ConnectionStream(ConnectionStream::Socket(std::move(socket)), tls_ ? &*tls_ : nullptr,
                               std::move(websocket)),
              std::move(peer), std::move(address));
      } else {
        admit(ConnectionStream(ConnectionStream::Socket(std::move(socket)), nullptr, nullptr),
              "unix:" + config_.unix_socket.string(), "unix");
      }
    } else {
      log_event("accept_failed", {{"reason", error.message()}});
      // Out of descriptors, say: accepting again at once would spin the I/O thread (and this
      // log) until one is free; the pending connection waits in the backlog meanwhile.
      auto retry = std::make_shared<asio::steady_timer>(io_, kAcceptRetry);
      retry->async_wait([this, &acceptor, retry](std::error_code) {
        if (!shutting_down_) accept_next(acceptor);
      });
      return;
    }
    accept_next(acceptor);
  });
}

void Server::admit(ConnectionStream stream, std::string peer, std::string address) {
  const std::uint64_t id = next_connection_id_++;
  if (stream.websocket()) ++websocket_connections_accepted_;
  auto connection =
      std::make_shared<Connection>(std::move(stream), id, std::move(peer), address, environment_);
  connections_.emplace(id, connection);
  builders_.set_connections(connections_.size());
  strangers_.forget([this](std::uint64_t stranger) {
    const auto found = connections_.find(stranger);
    return found != connections_.end() && found->second->stranger();
  });
  for (const StrangerSlots::Shed& shed : strangers_.admit(id, address)) {
    connections_.at(shed.id)->shed(
        shed.address_full
            ? "shed for a newer connection: " + address + " already holds " +
                  std::to_string(strangers_.per_address()) +
                  " connections that have not said Hello (--max-strangers-per-address)"
            : "shed for a newer connection: the server already holds " +
                  std::to_string(strangers_.total()) +
                  " connections that have not said Hello (--max-strangers)");
  }
  connection->start();
}

void Server::sweep_auth_bursts() {
  auth_burst_sweep_.expires_after(std::chrono::seconds(1));
  auth_burst_sweep_.async_wait([this](std::error_code error) {
    if (error || shutting_down_) return;
    log_auth_bursts(auth_backoff_.end_quiet_bursts(AuthBackoff::Clock::now()));
    sweep_auth_bursts();
  });
}

void Server::log_auth_bursts(const std::vector<AuthBackoff::Burst>& bursts) {
  const auto now = AuthBackoff::Clock::now();
  for (const AuthBackoff::Burst& burst : bursts) {
    log_event("auth_failure_burst",
              {{"address", burst.address},
               {"wrong_tokens", burst.failures},
               {"refused_unchecked", burst.refused},
               {"seconds", std::chrono::duration<double>(now - burst.started).count()}});
  }
}

void Server::run() {
  signals_.async_wait([this](std::error_code error, int signal) {
    if (!error) begin_shutdown(signal == SIGTERM ? "SIGTERM" : "SIGINT");
  });
  // Ready once the I/O thread runs its handlers (a SIGTERM already pending wins).
  asio::post(io_, [this]() {
    if (!shutting_down_) readiness_.set(Readiness::Stage::kAccepting);
  });
  sweep_auth_bursts();
  serving_ = true;
  io_.run();
  serving_ = false;
  worker_pool_.join();
  gpu_waiters_.join();
  if (!config_.unix_socket.empty()) {
    std::error_code ignored;
    std::filesystem::remove(config_.unix_socket, ignored);
  }
  log_event("stopped");
}

void Server::begin_shutdown(const char* reason) {
  if (shutting_down_) return;
  shutting_down_ = true;
  readiness_.set(Readiness::Stage::kDraining);
  log_event("shutdown", {{"reason", reason}, {"connections", connections_.size()}});
  std::error_code ignored;
  signals_.cancel(ignored);
  auth_burst_sweep_.cancel();
  // The bursts still going are logged now, with what they counted so far: two of the longest
  // waits ahead ends every one (AuthBackoff: quiet once its wait and max_wait have passed).
  log_auth_bursts(
      auth_backoff_.end_quiet_bursts(AuthBackoff::Clock::now() + 2 * auth_backoff_.max_wait()));
  if (tcp_acceptor_) tcp_acceptor_->close(ignored);
  if (websocket_acceptor_) websocket_acceptor_->close(ignored);
  if (unix_acceptor_) unix_acceptor_->close(ignored);
  if (vmc_) vmc_->close();
  // Copy: a connection that closes at once removes itself from the map (deferred anyway).
  const auto connections = connections_;
  for (const auto& [id, connection] : connections) connection->shut_down();
}

std::optional<ServerSnapshot> Server::snapshot(std::chrono::milliseconds timeout) {
  if (!serving_) return std::nullopt;
  auto promise = std::make_shared<std::promise<ServerSnapshot>>();
  std::future<ServerSnapshot> future = promise->get_future();
  asio::post(io_, [this, promise]() { promise->set_value(gather_snapshot()); });
  if (future.wait_for(timeout) != std::future_status::ready) return std::nullopt;
  return future.get();
}

ServerSnapshot Server::gather_snapshot() const {
  ServerSnapshot snapshot;
  snapshot.traffic = environment_.traffic;
  snapshot.all_connections = environment_.traffic.closed_connections;
  for (const auto& [id, connection] : connections_) {
    snapshot.all_connections.add(connection->counters());
    snapshot.poses_waiting += connection->poses_waiting();
    snapshot.poses_running += connection->pose_running() ? 1 : 0;
    snapshot.websocket_connections_open += connection->websocket() ? 1 : 0;
    snapshot.strangers_open += connection->stranger() ? 1 : 0;
  }
  snapshot.connections_open = connections_.size();
  snapshot.connections_accepted = next_connection_id_ - 1;
  snapshot.websocket_connections_accepted = websocket_connections_accepted_;
  snapshot.buffered_bytes = buffer_budget_.used();
  snapshot.work_bytes = work_budget_.used();
  snapshot.work_budget_bytes = work_budget_.limit();
  snapshot.work_refusals = work_budget_.refusals();
  snapshot.collision = environment_.collision.snapshot();
  if (vmc_) snapshot.vmc = vmc_->snapshots();
  for (const ModelHandle& model : environment_.models.models()) {
    ModelSnapshot& entry = snapshot.models.emplace_back();
    entry.id = model->id;
    entry.name = model->name;
    const auto counters = environment_.model_counters.find(model->id);
    if (counters != environment_.model_counters.end()) {
      entry.poses = counters->second.poses;
      entry.errors = counters->second.errors;
    }
  }
  return snapshot;
}

}  // namespace sweepd::server
