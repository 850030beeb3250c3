// Server: sweepd's listeners, connections and worker pool.
//
// Server(config, models, readiness, tls, gpu, collision): `tls`, when given, is the TCP and
//   WebSocket listeners' TLS (server/transport/tls_context.h); none: plain TCP. `gpu` (the one GPU
//   thread, for position maps) and `collision` (the collision backend) outlive the server.
// open(): binds the TCP listener (config.listen_address:port; port 0 picks a free one), the
//   WebSocket listener (config.ws_address:ws_port; TLS like the TCP one) and the Unix-socket
//   listener (config.unix_socket, a stale socket file is replaced; always plain) and the VMC
//   receivers' UDP sockets (config.vmc_listens, server/services/vmc/vmc_receivers.h). Throws
//   std::runtime_error naming the address and the reason. Returns the bound TCP port (0 with
//   no TCP listener); websocket_port() the bound WebSocket port (0: none).
// run(): serves until SIGTERM/SIGINT, then stops accepting, lets every
//   connection finish its in-flight work and say Bye, joins the workers and returns.
// snapshot(timeout): thread-safe; a copy of the counters and gauges (ServerSnapshot) taken on
//   the I/O thread, or nullopt when run() is not serving or the I/O thread did not answer
//   within `timeout`. Costs the I/O thread one pass over the open connections and models.
// `readiness` is set to accepting once run() serves and to draining on shutdown.
// Every connection is admitted as a stranger (StrangerSlots: past config.max_strangers in all
// or config.max_strangers_per_address from its address, the oldest stranger is shed with a
// fatal Error{ConnectionLimit}); a Hello with the right token past config.max_connections
// authenticated connections gets that error instead. Wrong tokens are counted per address
// (AuthBackoff); each burst of them is logged once it ends (`auth_failure_burst`).
// All socket work runs on the thread that calls run(); deformation and model loading run on
// a pool of config.worker_threads (0: one per core); poses whose folding waits on the GPU
// thread (the gpu collision backend) run on a second pool of as many threads, which mostly
// wait, so that the first stays free for other connections' CPU work.
#pragma once

#include <asio.hpp>
#include <asio/ssl/context.hpp>
#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <optional>

#include "server/config.h"
#include "server/models/model_service.h"
#include "server/readiness.h"
#include "server/services/collision_service.h"
#include "server/services/gpu_thread.h"
#include "server/services/position_map_service.h"
#include "server/services/spare_cores.h"
#include "server/transport/connection.h"
#include "server/transport/server_snapshot.h"
#include "server/transport/stranger_slots.h"

namespace sweepd::server {

class Server {
 public:
  Server(const ServerConfig& config, ModelService& models, Readiness& readiness,
         std::optional<asio::ssl::context> tls, GpuThread& gpu, CollisionService& collision);
  ~Server();

  int open();
  int websocket_port() const { return websocket_port_; }
  const std::vector<int>& vmc_ports() const { return vmc_ports_; }  // --vmc-listen's order
  void run();
  std::optional<ServerSnapshot> snapshot(std::chrono::milliseconds timeout);

 private:
  template <typename Acceptor>
  void accept_next(Acceptor& acceptor);
  // Binds config address:port; the bound port. Throws naming `what`, the address and why.
  int listen_tcp(std::optional<asio::ip::tcp::acceptor>& acceptor, const std::string& address,
                 int port, const char* what);
  void admit(ConnectionStream stream, std::string peer, std::string address);
  // Every second: logs the bursts of wrong tokens that have ended.
  void sweep_auth_bursts();
  void log_auth_bursts(const std::vector<AuthBackoff::Burst>& bursts);
  void begin_shutdown(const char* reason);
  ServerSnapshot gather_snapshot() const;  // on the I/O thread

  const ServerConfig& config_;
  Readiness& readiness_;
  std::atomic<bool> serving_{false};  // io_.run() is (about to be) running
  asio::io_context io_;
  asio::thread_pool worker_pool_;
  SpareCores spare_cores_;  // the workers' cores no job holds: one large pose may split over them
  FairWorkQueue workers_;  // joined with worker_pool_ (its tokens hold it)
  asio::thread_pool gpu_waiters_;
  PositionMapService position_maps_;
  ContactSheetService contact_sheets_;  // renders on position_maps_'s GPU worker
  ClipStore clips_;                     // UploadClip's clips, shared by every connection
  protocol::BufferBudget buffer_budget_;
  WorkBudget work_budget_;
  ReplyBuilderPool builders_;
  asio::signal_set signals_;
  std::optional<asio::ssl::context> tls_;  // the TCP listener's TLS; none: plain
  std::optional<asio::ip::tcp::acceptor> tcp_acceptor_;
  std::optional<asio::ip::tcp::acceptor> websocket_acceptor_;
  int websocket_port_ = 0;
  std::optional<asio::local::stream_protocol::acceptor> unix_acceptor_;
  std::unique_ptr<VmcReceivers> vmc_;  // null without --vmc-listen
  std::vector<int> vmc_ports_;
  AuthBackoff auth_backoff_;
  ConnectionEnvironment environment_;
  StrangerSlots strangers_;
  asio::steady_timer auth_burst_sweep_;
  std::map<std::uint64_t, std::shared_ptr<Connection>> connections_;
  std::uint64_t next_connection_id_ = 1;
  std::uint64_t websocket_connections_accepted_ = 0;
  bool shutting_down_ = false;
};

}  // namespace sweepd::server
