// HttpSidePort: sweepd's HTTP side port (--http-listen), apart from the protocol port, for
// operators' tools: GET /healthz (200 while the process runs), GET /readyz (200 only while
// `readiness` is accepting; 503 naming the stage otherwise: restoring the store, binding the
// default model, opening the listeners, draining after SIGTERM) and GET /metrics (the
// Prometheus text page of format_metrics) and GET /viewer, /viewer/ and /viewer/NAME (the
// browser viewer: index.html, or the file NAME of `viewer`, from memory; a 404 saying why when
// there is no such file, or no viewer because sweepd has no --viewer-dir). HEAD too; anything
// else: 404 (405 for other methods). The answers: server/http/side_port_answers.h.
//
// Probes answer under abuse (issue 49 item 3). One thread of its own (Asio, never the
// protocol's I/O thread) reads every request head without blocking and answers /healthz,
// /readyz and /viewer at once from memory, so a probe never waits behind another request;
// /metrics, which waits for the protocol's I/O thread (`snapshot`: Server::snapshot, copied
// there, or nullopt), is formatted on a second thread, at most kMaxMetricsWaiting at once (more
// get 503). A request head must be whole within kHeadDeadline (else 408 and closed: slow
// headers hold nothing for long) and at most kMaxRequestHeadBytes (else 431). Connections whose
// head is not whole yet are held at most kMaxReadingPerAddress from one address and kMaxReading
// in all; past either the oldest is closed (StrangerSlots), so slow or many peers cannot keep a
// probe's connection from being read. Every answer closes its connection (Connection: close),
// and must be taken within kAnswerDeadline.
// Binds in the constructor (throws std::runtime_error naming the address), serves until
// destroyed. SIGPIPE is ignored process-wide: a scraper that hangs up must not kill the daemon.
#pragma once

#include <asio.hpp>
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "server/http/viewer_files.h"
#include "server/readiness.h"
#include "server/transport/server_snapshot.h"
#include "server/transport/stranger_slots.h"

namespace sweepd::server {

class HttpSidePort {
 public:
  using SnapshotSource = std::function<std::optional<ServerSnapshot>()>;

  static constexpr std::chrono::milliseconds kHeadDeadline{2000};
  static constexpr std::chrono::milliseconds kAnswerDeadline{5000};
  static constexpr std::size_t kMaxReading = 64;
  static constexpr std::size_t kMaxReadingPerAddress = 8;
  static constexpr int kMaxMetricsWaiting = 4;

  // port 0: a free one (see port()). `viewer`: the files served under /viewer (nullptr:
  // none); it must outlive this.
  HttpSidePort(const std::string& address, int port, const Readiness& readiness,
               SnapshotSource snapshot, const ViewerFiles* viewer = nullptr);
  ~HttpSidePort();
  HttpSidePort(const HttpSidePort&) = delete;
  HttpSidePort& operator=(const HttpSidePort&) = delete;

  int port() const { return port_; }

 private:
  class Exchange;  // one connection: its request head read, its answer written

  void accept_next();
  void admit(asio::ip::tcp::socket socket);
  std::shared_ptr<Exchange> find(std::uint64_t id) const;  // nullptr once closed
  // /metrics on the metrics thread; the answer is written back on the side port's thread.
  void answer_metrics(std::shared_ptr<Exchange> exchange, bool head_only);

  const Readiness& readiness_;
  SnapshotSource snapshot_;
  const ViewerFiles* viewer_;
  asio::io_context io_;
  asio::ip::tcp::acceptor acceptor_;
  asio::steady_timer accept_retry_;  // after a failed accept
  asio::thread_pool metrics_thread_{1};
  int metrics_waiting_ = 0;  // on the side port's thread
  StrangerSlots reading_;    // connections whose request head is not whole yet
  std::map<std::uint64_t, std::weak_ptr<Exchange>> exchanges_;
  std::uint64_t next_exchange_ = 1;
  int port_ = 0;
  std::thread thread_;
};

}  // namespace sweepd::server
